//! Typed uniforms: each program's uniform locations live in one struct made from one list of names
//! ([`uniforms!`](crate::uniforms)), looked up once when the program is built. A name that the
//! program's sources do not declare is an error naming the files, unless the list marks it optional
//! and says why; so a typo, in the list or in the shader, cannot draw silently wrong with a uniform
//! that is never set. A declared uniform the shader does not use (the GLSL compiler removes it) is
//! not an error: a learner's live edit that stops using one still loads.

use crate::common::shader::Program;
use crate::{Error, Result};

/// A uniform's location: `None` only for one marked optional that the program lacks (GL ignores
/// `glUniform*` on `None`, as it does on location -1).
pub type Uniform = Option<glow::UniformLocation>;

/// The location of `name` in `program`. A name the program lacks is fine if its sources declare it
/// (the shader does not use it, so the compiler removed it: a learner's live edit often does that)
/// or if the list marks it `optional`; otherwise it is an error naming the files.
pub fn locate(program: &Program, name: &str, optional: bool) -> Result<Uniform> {
    let location = program.uniform(name);
    if location.is_none() {
        if program.declared_uniforms.iter().any(|n| n == name) {
            log::debug!(
                "{}: uniform '{name}' is declared but not used",
                program.files.display()
            );
        } else if !optional {
            return Err(Error::Shader {
                path: program.files.clone(),
                stage: "uniform look-up",
                log: format!("no uniform '{name}' is declared (misspelt, here or in the shader?)"),
            });
        }
    }
    Ok(location)
}

/// Declares a struct of a program's uniform locations from one list of `field: "GlslName"` pairs
/// (`field: "GlslName" optional("why")` may be missing from the program):
/// - `struct X for Program { .. }`: the struct holds the program too (`program`), made by
///   `X::new(program)`;
/// - `struct X { .. }`: the locations alone (a program's extra uniforms), made by `X::locate(&program)`.
#[macro_export]
macro_rules! uniforms {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident for Program {
            $($field:ident: $glsl:literal $(optional($why:literal))?),* $(,)?
        }
    ) => {
        $(#[$meta])*
        $vis struct $name {
            pub program: $crate::common::shader::Program,
            $(pub $field: $crate::gl::uniforms::Uniform,)*
        }

        impl $name {
            /// The program with every location of the list.
            pub fn new(program: $crate::common::shader::Program) -> $crate::Result<Self> {
                Ok($name {
                    $($field: $crate::uniforms!(@locate program, $glsl $(, $why)?),)*
                    program,
                })
            }
        }
    };
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $($field:ident: $glsl:literal $(optional($why:literal))?),* $(,)?
        }
    ) => {
        $(#[$meta])*
        $vis struct $name {
            $(pub $field: $crate::gl::uniforms::Uniform,)*
        }

        impl $name {
            /// Every location of the list, looked up in `program`.
            pub fn locate(program: &$crate::common::shader::Program) -> $crate::Result<Self> {
                Ok($name {
                    $($field: $crate::uniforms!(@locate program, $glsl $(, $why)?),)*
                })
            }
        }
    };
    (@locate $program:ident, $glsl:literal) => {
        $crate::gl::uniforms::locate(&$program, $glsl, false)?
    };
    (@locate $program:ident, $glsl:literal, $why:literal) => {
        $crate::gl::uniforms::locate(&$program, $glsl, true)?
    };
}
