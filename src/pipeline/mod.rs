//! The first frame's CPU work at the size of a learner's model: the same results as the tutorial's
//! ports in [`crate::common`], to the bit, in a fraction of the time. The program calls these; the
//! ports stay as the tutorial reads, and the tests compare the two.
//!
//! | module          | ports                                  | how                                  |
//! |-----------------|----------------------------------------|--------------------------------------|
//! | [`indexer`]     | `indexVBO_TBN`, `indexVBO`             | exact numbering, then a hash grid    |
//! | [`obj_parse`]   | `loadOBJ`                              | the file's lines split over the cores |
//! | [`mikktspace`]  | the `mikktspace` crate (MikkTSpace)    | hashed weld, runs of groups per core  |

pub mod indexer;
pub mod mikktspace;
pub mod obj_parse;
