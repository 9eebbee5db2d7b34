//! Switches with named values (`--tangents`, `--space`): clap's `ValueEnum` gives each value its
//! command-line name, parses it and lists the values; these give what a key and the panel need on
//! top: the names in order, and a value found by its name.

use clap::ValueEnum;

/// `value`'s command-line name, for the title and the log.
pub fn name<T: ValueEnum>(value: &T) -> String {
    value
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string())
}

/// Every value's command-line name, in order (the choices a key steps through).
pub fn names<T: ValueEnum>() -> Vec<String> {
    T::value_variants().iter().map(name).collect()
}

/// The value whose command-line name is `name`, if any.
pub fn by_name<T: ValueEnum + Clone>(name: &str) -> Option<T> {
    let all = T::value_variants();
    all.iter().find(|v| self::name(*v) == name).cloned()
}
