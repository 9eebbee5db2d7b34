//! Switches with named values (`--tangents`, `--space`): clap's `ValueEnum` gives each value its
//! command-line name, parses it and lists the values; [`name`] gives a value's name for the title,
//! the panel and the log (a scene's table steps through its own typed list of values).

use clap::ValueEnum;

/// `value`'s command-line name, for the title and the log.
pub fn name<T: ValueEnum>(value: &T) -> String {
    value
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string())
}
