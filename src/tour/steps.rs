//! The tour's steps: one per section of the tutorial's page, in its order. Each caption is this
//! project's own text; each code reference is resolved from the source the binary is built from
//! (`tests/all/tour.rs` resolves them all), and each C++ range was counted on the file at the
//! commit `original.rs` links to.

use super::original::{Cpp, CppFile};
use super::{Camera, State, Step, Value};

const CYLINDER: &str = "cylinder";
const FRAGMENT: &str = "shaders/NormalMapping.fragmentshader";
const VERTEX: &str = "shaders/NormalMapping.vertexshader";

/// The cylinder as it starts, with `controls` set.
const fn cylinder(controls: &'static [(&'static str, Value)]) -> State {
    State {
        scene: CYLINDER,
        controls,
        camera: Camera::Start,
    }
}

const fn main_lines(first: u32, last: u32, what: &'static str) -> Cpp {
    Cpp {
        file: CppFile::Tutorial13,
        function: "main",
        lines: (first, last),
        what,
    }
}

const fn tangent_basis_lines(first: u32, last: u32, what: &'static str) -> Cpp {
    Cpp {
        file: CppFile::TangentSpace,
        function: "computeTangentBasis",
        lines: (first, last),
        what,
    }
}

/// Every step, in the tutorial's order.
pub static STEPS: [Step; 18] = [
    Step {
        section: "Normal textures",
        name: "normal-textures",
        caption:
            "A normal map keeps one direction per texel: red, green and blue are its x, y and \
                  z, taken from -1..1 to 0..255, so a flat texel is (128, 128, 255), the pale blue \
                  of most maps. The colour view \"normal01\" shows the map's normals as the shader \
                  reads them. V steps through the views; \"lit\" is the lit frame.",
        state: cylinder(&[("colour view", Value::Choice("normal01"))]),
        rust: &["common::texture::load_bmp_custom"],
        regions: &[(FRAGMENT, "normal")],
        cpp: &[
            main_lines(
                94,
                102,
                "the three textures loaded, their samplers' handles",
            ),
            Cpp {
                file: CppFile::Texture,
                function: "loadBMP_custom",
                lines: (10, 94),
                what: "the BMP read and uploaded, mipmaps generated",
            },
        ],
    },
    Step {
        section: "Tangent and Bitangent",
        name: "tangent-and-bitangent",
        caption: "The map's directions are in tangent space: x runs along the texture's U (the \
                  tangent, red lines), y along its V (the bitangent, green), z out of the surface \
                  (the normal, blue). L shows the three at every corner. Each triangle's T and B \
                  come from its two edges solved against its two steps in UV.",
        state: cylinder(&[("TBN debug lines", Value::On(true))]),
        rust: &[],
        regions: &[("src/common/tangentspace.rs", "solve")],
        cpp: &[tangent_basis_lines(
            28,
            38,
            "the edges and UV steps, solved for T and B",
        )],
    },
    Step {
        section: "Computing the tangents and bitangents",
        name: "computing-tangents",
        caption: "The OBJ loader gives a soup of triangles, three corners each; \
                  computeTangentBasis solves one tangent and one bitangent per triangle and gives \
                  them to its three corners. Nothing to press: this is the CPU half of the \
                  set-up, before anything is drawn.",
        state: cylinder(&[]),
        rust: &[
            "scenes::cylinder::tutorial13::load_mesh",
            "common::tangentspace::compute_tangent_basis",
        ],
        regions: &[],
        cpp: &[
            main_lines(104, 115, "loadOBJ, then computeTangentBasis"),
            tangent_basis_lines(16, 51, "per triangle: T and B for its three corners"),
        ],
    },
    Step {
        section: "Indexing",
        name: "indexing",
        caption: "indexVBO_TBN keeps a corner as a new vertex unless an earlier vertex has its \
                  position, UV and normal within 0.01; that vertex then gets the corner's tangent \
                  and bitangent added to its own (a sum: the shader normalizes). The lines, \
                  lengthened here with the panel's slider, show one summed frame per vertex. This \
                  cylinder runs the port; above 2 048 triangles a hash grid gives the same mesh.",
        state: cylinder(&[
            ("TBN debug lines", Value::On(true)),
            ("TBN line length", Value::Slider(0.3)),
        ]),
        rust: &[
            "common::vboindexer::index_vbo_tbn",
            "common::vboindexer::get_similar_vertex_index",
            "common::vboindexer::is_near",
            "mesh::index_vbo_tbn_by_size",
        ],
        regions: &[],
        cpp: &[
            main_lines(117, 126, "indexVBO_TBN called"),
            Cpp {
                file: CppFile::VboIndexer,
                function: "indexVBO_TBN",
                lines: (141, 177),
                what: "each corner found or added, its tangents summed",
            },
            Cpp {
                file: CppFile::VboIndexer,
                function: "getSimilarVertexIndex",
                lines: (19, 47),
                what: "the linear search for a near vertex",
            },
            Cpp {
                file: CppFile::VboIndexer,
                function: "is_near",
                lines: (12, 14),
                what: "the 0.01 tolerance",
            },
        ],
    },
    Step {
        section: "The additional buffers and uniforms",
        name: "buffers-and-uniforms",
        caption: "Two more vertex attributes, tangents at location 3 and bitangents at 4, and one \
                  more uniform, MV3x3: the upper 3×3 of the model-view matrix, which turns \
                  directions into camera space. MeshBuffers uploads the five arrays in one loop.",
        state: cylinder(&[]),
        rust: &[
            "gl::buffers::MeshBuffers::new",
            "scenes::cylinder::tutorial13::NormalMappingProgram",
        ],
        regions: &[(VERTEX, "tangent-attributes"), (VERTEX, "mv3x3")],
        cpp: &[
            main_lines(145, 153, "the tangent and bitangent buffers"),
            main_lines(187, 202, "the matrices, MV3x3 among them, sent"),
            main_lines(263, 285, "attributes 3 and 4"),
        ],
    },
    Step {
        section: "The vertex shader",
        name: "vertex-shader",
        caption: "The vertex shader puts the camera-space tangent, bitangent and normal in a \
                  matrix and uses its transpose to carry the light and eye directions into \
                  tangent space. The colour view \"light01\" shows the light direction it hands \
                  on, mapped to 0..1.",
        state: cylinder(&[("colour view", Value::Choice("light01"))]),
        rust: &[],
        regions: &[(VERTEX, "tbn")],
        cpp: &[main_lines(85, 86, "the two shaders loaded")],
    },
    Step {
        section: "The fragment shader",
        name: "fragment-shader",
        caption: "The fragment shader reads the normal from the map (V turned back for the BMP) \
                  and lights with it in tangent space: ambient, diffuse and specular as before, \
                  with every direction normalized first. The lit frame is back.",
        state: cylinder(&[]),
        rust: &["scenes::cylinder::tutorial13::Tutorial13::draw_mesh_with"],
        regions: &[(FRAGMENT, "normal"), (FRAGMENT, "lighting")],
        cpp: &[main_lines(
            205,
            224,
            "the light and the three texture units",
        )],
    },
    Step {
        section: "Results",
        name: "results",
        caption: "The tutorial's first frame, which this program draws pixel for pixel as the \
                  C++ original does on the same Mesa. The arrow keys move the camera and the \
                  mouse turns it once a click on the frame has grabbed the cursor; R brings it \
                  back.",
        state: cylinder(&[]),
        rust: &["scenes::cylinder::tutorial13::Tutorial13::new"],
        regions: &[],
        cpp: &[main_lines(169, 302, "the loop up to the draw")],
    },
    Step {
        section: "Orthogonalization",
        name: "orthogonalization",
        caption: "A tangent solved from the UVs is not quite at right angles to the normal. \
                  Gram-Schmidt takes its part along the normal out and normalizes the rest. G \
                  turns that off, as here: against the blue normals, the red tangents lean.",
        state: cylinder(&[
            ("Gram-Schmidt", Value::On(false)),
            ("TBN debug lines", Value::On(true)),
        ]),
        rust: &[
            "common::tangentspace::orthogonalize_corner",
            "common::tangentspace::gram_schmidt",
        ],
        regions: &[],
        cpp: &[tangent_basis_lines(
            53,
            61,
            "per corner: Gram-Schmidt against the normal",
        )],
    },
    Step {
        section: "Handedness",
        name: "handedness",
        caption: "Where the UVs are mirrored the solved frame turns the other way; the tutorial \
                  tests cross(n, t) against b and turns t round where they disagree. Seen \
                  through the loader's negated V, the tutorial's cylinder is mirrored everywhere: \
                  with H off, as here, the bumps are lit from the wrong side.",
        state: cylinder(&[("handedness fix", Value::On(false))]),
        rust: &[],
        regions: &[("src/common/tangentspace.rs", "handedness")],
        cpp: &[tangent_basis_lines(
            63,
            66,
            "per corner: the handedness test",
        )],
    },
    Step {
        section: "Specular texture",
        name: "specular-texture",
        caption: "A third map sets how strong the highlight is at each texel. S swaps it for the \
                  constant 0.3 of the earlier tutorials, as here; press S again to see the map's \
                  highlights.",
        state: cylinder(&[("specular texture", Value::On(false))]),
        rust: &["common::texture::load_dds"],
        regions: &[(FRAGMENT, "material")],
        cpp: &[
            main_lines(94, 97, "the specular map loaded with the others"),
            main_lines(220, 224, "bound to texture unit 2"),
        ],
    },
    Step {
        section: "Debugging with the immediate mode",
        name: "immediate-mode",
        caption: "The tutorial draws its T, B and N lines with glBegin and glEnd, which only a \
                  compatibility context has. L draws them: in the tutorial's immediate mode \
                  under --profile compat, with a small line shader in a core context (M \
                  chooses). The white cross is the light.",
        state: State {
            scene: CYLINDER,
            controls: &[("TBN debug lines", Value::On(true))],
            camera: Camera::At {
                position: [0.4, 0.9, 2.6],
                horizontal_angle: 3.3,
                vertical_angle: -0.5,
            },
        },
        rust: &[
            "debug::lines::DebugLines::draw_legacy",
            "debug::lines::light_cross",
        ],
        regions: &[],
        cpp: &[main_lines(
            305,
            364,
            "the debug block: the fixed-function matrices, lines for N, T, B and the light",
        )],
    },
    Step {
        section: "Debugging with colors",
        name: "colors",
        caption: "Write a vector as the colour and look at it. V steps through the light \
                  direction, the eye direction and the map's normal (raw, or mapped to 0..1 with \
                  \"01\"); C picks one component, in grey. Here, the light direction's z: bright \
                  where the light faces the surface head on.",
        state: cylinder(&[
            ("colour view", Value::Choice("light")),
            ("component", Value::Choice("z")),
        ]),
        rust: &["debug::views::ColorView"],
        regions: &[("shaders/NormalMappingDebug.fragmentshader", "colour-view")],
        cpp: &[],
    },
    Step {
        section: "Debugging with variable names",
        name: "variable-names",
        caption: "Every vector's name ends with its space (_modelspace, _cameraspace, \
                  _tangentspace), and a sum or a dot product only ever takes vectors of one \
                  space. The tutorial's code keeps the habit, and so does this port, in Rust and \
                  GLSL alike.",
        state: cylinder(&[]),
        rust: &["common::controls::Controls::compute_matrices_from_inputs"],
        regions: &[(VERTEX, "spaces")],
        cpp: &[],
    },
    Step {
        section: "How to create a normal map",
        name: "create-a-normal-map",
        caption: "Three ways, a command each. Generated from a height map: tutorial13 normalmap \
                  HEIGHT.png -o normal.png --strength S (this cylinder's map was made so). Baked \
                  from a detailed model: tutorial13 bake HIGH.obj LOW.obj -o normal.png. Two maps \
                  combined: tutorial13 normalmap --combine BASE.png DETAIL.png -o normal.png. The \
                  panel's normal strength scales x and y as --strength does: 2 here.",
        state: cylinder(&[
            ("colour view", Value::Choice("normal01")),
            ("normal strength", Value::Slider(2.0)),
        ]),
        rust: &["normalmap::normal_map", "combine::combine_maps"],
        regions: &[],
        cpp: &[],
    },
    Step {
        section: "Exercises: normalize before summing",
        name: "exercise-1",
        caption: "Normalize each corner's tangent and bitangent in index_vbo_tbn \
                  (src/common/vboindexer.rs) before they are added, so that large triangles stop \
                  outweighing small ones. Rebuild, run tutorial13 --tour exercise-1 and press F2 (or \
                  tutorial13 --headless --check-exercise 1). N shows the answer.",
        state: cylinder(&[]),
        rust: &[
            "common::vboindexer::index_vbo_tbn",
            "common::vboindexer::Builder::add_sums",
        ],
        regions: &[],
        cpp: &[Cpp {
            file: CppFile::VboIndexer,
            function: "indexVBO_TBN",
            lines: (162, 167),
            what: "a found corner's tangents added to its vertex's",
        }],
    },
    Step {
        section: "Exercises: the eye direction as colour",
        name: "exercise-2",
        caption: "Copy shaders/ to a folder of your own and make NormalMapping.fragmentshader's \
                  colour normalize(EyeDirection_tangentspace); run with --shaders DIR (F5 reloads \
                  it in the window), then press F2 here to compare it with the colour view \"eye\" \
                  (or tutorial13 --headless --check-exercise 2 --shaders DIR).",
        state: cylinder(&[]),
        rust: &[],
        regions: &[(FRAGMENT, "lighting")],
        cpp: &[],
    },
    Step {
        section: "Tools & Links",
        name: "tools-and-links",
        caption: "Normal maps from photographs, without a 3D tool: tutorial13 photometric \
                  (several photos under known lights) or tutorial13 normalmap --from-photo (one \
                  photo's guess). Enter steps through the programs of three more normal-mapping \
                  articles, this 2D sprite first.",
        state: State {
            scene: "sprite",
            controls: &[],
            camera: Camera::Start,
        },
        rust: &["photometric::photo::height_from_photo"],
        regions: &[],
        cpp: &[],
    },
];
