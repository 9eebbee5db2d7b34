//! Every integration test in one binary: one link instead of one per file, and one process whose
//! helpers (`common`) are compiled once. Each module is one former test file, named for what it
//! checks; run one with `cargo test --release -- <module>::` (see the README).

#[path = "../support/capture_rig.rs"]
mod capture_rig;
mod common;
#[path = "../support/differential.rs"]
mod differential;
#[path = "../support/mikktspace_reference.rs"]
mod mikktspace_reference;

mod asset_fallback;
mod assets;
mod bake;
mod bake_cage;
mod cli;
mod combine;
mod compare_view;
mod context;
mod debug_lines;
mod docs;
mod flags_and_files;
mod fuzz;
mod gl_helpers;
mod gltf;
mod live_shaders;
mod mikktspace;
mod model;
mod normal_map_conventions;
mod normalmap;
mod obj_input;
mod one_cell;
mod panel;
mod photometric;
mod pipeline;
mod render;
mod runner;
mod scene_added;
mod scene_cube;
mod scene_sprite;
mod scene_wall;
mod scenes;
mod table;
mod tangent_overflow;
mod tangent_sources;
mod texture;
mod tour;
mod tour_pane;
mod views;
mod web;
mod window_input;
