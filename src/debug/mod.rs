//! The tutorial's debugging aids, given what they draw (a mesh, a light position) and never reaching
//! back into a scene: the TBN lines of "Debugging with the immediate mode" ([`lines`]) and the colour
//! views of "Debugging with colors" ([`views`]).

pub mod compare;
pub mod lines;
pub mod views;
