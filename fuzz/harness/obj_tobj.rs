//! The `obj-tobj` target: the project's OBJ reader against tobj's parse.

use std::path::Path;

use tutorial13::pipeline::obj_parse::load_obj_bytes_threaded;

use super::model::split_model_input;
use super::{rejected, Outcome};
use crate::differential::differ_from_tobj;

/// The `obj-tobj` target's check (see [`Target::ObjTobj`](super::Target::ObjTobj)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    let (obj, mtl) = split_model_input(input);
    differ_from_tobj(&obj, &mtl)?;
    match load_obj_bytes_threaded(&obj, path) {
        Err(e) => rejected(path, e),
        Ok(_) => Ok(Outcome::Loaded),
    }
}
