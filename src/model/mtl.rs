//! The texture statements of a `.mtl` file (`map_Kd`, `map_Bump`, `bump`, `norm`, `map_Ks`).
//!
//! tobj parses the file and keeps the rest of each texture line as one string, options included
//! (`-bm 0.5 textures\brick normal.png`). This reads that string: the options the MTL format
//! defines are taken off the front (each with its count of arguments), and what is left is the file
//! name, spaces and all, with Windows' backslashes turned into slashes.

/// Checks what tobj's MTL parser would panic on rather than refuse (tobj 4.0.5 unwraps a colour
/// of fewer than three numbers): `Ka`, `Kd`, `Ks`, `Ke` need three.
pub fn check_mtl(text: &str) -> Result<(), String> {
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(keyword @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            if words.count() < 3 {
                return Err(format!(
                    "line {}: {keyword} needs three numbers (r g b)",
                    number + 1
                ));
            }
        }
    }
    Ok(())
}

/// One texture statement, read.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureStatement {
    /// The file as written, backslashes made slashes.
    pub file: String,
    /// `-bm S`: the bump multiplier (a normal map's x and y are scaled by it).
    pub bump_multiplier: Option<f32>,
    /// Options the program does not apply, as written (`-s 2 2`), for a notice.
    pub ignored: Vec<String>,
}

/// The options of the MTL format and how many arguments each takes; `-o`, `-s` and `-t` take one
/// to three numbers (marked 0 here: as many as follow, up to three).
const OPTIONS: [(&str, usize); 13] = [
    ("-blendu", 1),
    ("-blendv", 1),
    ("-bm", 1),
    ("-boost", 1),
    ("-cc", 1),
    ("-clamp", 1),
    ("-imfchan", 1),
    ("-mm", 2),
    ("-o", 0),
    ("-s", 0),
    ("-t", 0),
    ("-texres", 1),
    ("-type", 1),
];

/// Reads `text`, the part of a texture line after its keyword. Errors say what is wrong.
pub fn parse_texture_statement(text: &str) -> Result<TextureStatement, String> {
    let mut rest = text.trim();
    let mut statement = TextureStatement {
        file: String::new(),
        bump_multiplier: None,
        ignored: Vec::new(),
    };
    loop {
        let (word, after) = split_word(rest);
        let Some(&(option, count)) = OPTIONS.iter().find(|(name, _)| *name == word) else {
            break; // the file name (which may itself start with '-')
        };
        rest = after;
        let mut arguments = Vec::new();
        let (min, max) = if count == 0 { (1, 3) } else { (count, count) };
        while arguments.len() < max {
            let (argument, after) = split_word(rest);
            // -o/-s/-t end at the first word that is not a number (the file name).
            if argument.is_empty() || (count == 0 && argument.parse::<f32>().is_err()) {
                break;
            }
            arguments.push(argument);
            rest = after;
        }
        if arguments.len() < min {
            return Err(format!("option {option} needs {min} argument(s)"));
        }
        if option == "-bm" {
            let multiplier = arguments[0]
                .parse::<f32>()
                .ok()
                .filter(|m| m.is_finite())
                .ok_or_else(|| format!("-bm {}: not a finite number", arguments[0]))?;
            statement.bump_multiplier = Some(multiplier);
        } else {
            statement
                .ignored
                .push(format!("{option} {}", arguments.join(" ")));
        }
    }
    if rest.is_empty() {
        return Err("no file name after the options".into());
    }
    statement.file = rest.replace('\\', "/");
    Ok(statement)
}

/// The first whitespace-separated word of `s`, and the rest with its leading whitespace removed.
fn split_word(s: &str) -> (&str, &str) {
    let s = s.trim_start();
    let end = s.find(char::is_whitespace).unwrap_or(s.len());
    (&s[..end], s[end..].trim_start())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> TextureStatement {
        parse_texture_statement(text).unwrap()
    }

    // Fails if a plain name, a name with spaces or a Windows path is not kept as the file.
    #[test]
    fn file_names_keep_spaces_and_lose_backslashes() {
        assert_eq!(parse("brick.png").file, "brick.png");
        assert_eq!(parse("  my brick map.png ").file, "my brick map.png");
        assert_eq!(parse(r"textures\brick.png").file, "textures/brick.png");
        assert_eq!(
            parse(r"C:\Users\me\brick.png").file,
            "C:/Users/me/brick.png"
        );
    }

    // Fails if options are taken as part of the file name, or -bm is not read.
    #[test]
    fn options_come_off_the_front() {
        let s = parse("-bm 0.5 -s 2 2 1 -o 0.1 normal map.png");
        assert_eq!(s.file, "normal map.png");
        assert_eq!(s.bump_multiplier, Some(0.5));
        assert_eq!(s.ignored, ["-s 2 2 1", "-o 0.1"]);
        // -s with one number, then a name that is not a number.
        assert_eq!(parse("-s 2 bricks.jpg").file, "bricks.jpg");
        assert_eq!(parse("-clamp on -imfchan l height.png").ignored.len(), 2);
        // An unknown dash word starts the file name.
        assert_eq!(parse("-weird.png").file, "-weird.png");
    }

    // Fails if a colour of fewer than three numbers reaches tobj (which panics on it).
    #[test]
    fn short_colours_are_refused() {
        assert!(check_mtl("newmtl a\nKd 0.8 0.8 0.8\nKs 1 1 1 # shiny\n").is_ok());
        let e = check_mtl("newmtl a\n  Kd 0.8 0.8\n").unwrap_err();
        assert!(e.contains("line 2: Kd needs three"), "{e}");
    }

    // Fails if a statement without a file, or a bad -bm, is accepted.
    #[test]
    fn bad_statements_say_why() {
        for (text, reason) in [
            ("-bm 0.5", "no file name"),
            ("", "no file name"),
            ("-bm", "needs 1"),
            ("-bm x a.png", "not a finite"),
            ("-bm inf a.png", "not a finite"),
            ("-mm 0", "needs 2"),
            ("-s", "needs 1"),
        ] {
            let e = parse_texture_statement(text).unwrap_err();
            assert!(e.contains(reason), "{text:?}: {e}");
        }
    }
}
