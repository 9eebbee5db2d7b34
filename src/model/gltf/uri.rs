//! What a glTF's URIs name: its buffers' bytes (the GLB's binary chunk, a `data:` URI, or a file
//! beside the model), with the percent escapes and the base64 they are written in.

use super::Reader;

impl Reader<'_> {
    /// Every buffer's bytes: the GLB's BIN chunk, a data URI, or a file beside the model.
    pub(super) fn buffers(
        &self,
        document: &gltf::Document,
        mut blob: Option<Vec<u8>>,
    ) -> Result<Vec<Vec<u8>>, String> {
        let mut out = Vec::new();
        for buffer in document.buffers() {
            let what = format!("buffer {}", buffer.index());
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| format!("{what}: the file has no binary chunk"))?,
                gltf::buffer::Source::Uri(uri) => self.uri(uri, &what)?,
            };
            if data.len() < buffer.length() {
                return Err(format!(
                    "{what}: {} bytes where the file says {}: cut short",
                    data.len(),
                    buffer.length()
                ));
            }
            out.push(data);
        }
        Ok(out)
    }

    /// A buffer's or an image's URI: a `data:` URI decoded, or a file beside the model.
    pub(super) fn uri(&self, uri: &str, what: &str) -> Result<Vec<u8>, String> {
        if let Some(data) = uri.strip_prefix("data:") {
            let (header, payload) = data
                .split_once(',')
                .ok_or_else(|| format!("{what}: a data URI without a comma"))?;
            if !header.ends_with(";base64") {
                return Err(format!("{what}: a data URI that is not base64"));
            }
            return decode_base64(payload).ok_or_else(|| format!("{what}: malformed base64"));
        }
        let name = percent_decode(uri)
            .ok_or_else(|| format!("{what}: malformed URI '{}'", one_line(uri)))?;
        let file = self.folder.join(&name);
        (self.read_file)(&file)
            .map_err(|e| format!("{what}: {}: {e}", one_line(&file.display().to_string())))
    }
}

/// `text` with its control characters (a line break in a file's URI) escaped, so that an error
/// naming it stays one line.
fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| match c.is_control() {
            true => c.escape_default().to_string(),
            false => c.to_string(),
        })
        .collect()
}

/// A URI's `%XX` escapes decoded (a file name with spaces is written `%20`).
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Standard base64 (RFC 4648, with or without padding), as data URIs carry it.
pub fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let text = text.trim_end_matches('=').as_bytes();
    if text.len() % 4 == 1 {
        return None;
    }
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    for chunk in text.chunks(4) {
        let mut bits = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            bits |= value(c)? << (18 - 6 * k);
        }
        let bytes = bits.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Some(out)
}

/// Standard base64 with padding: what a data URI carries (for tools and tests that write glTF).
pub fn encode_base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let mut bits = 0u32;
        for (k, &b) in chunk.iter().enumerate() {
            bits |= u32::from(b) << (16 - 8 * k);
        }
        for k in 0..4 {
            match k <= chunk.len() {
                true => out.push(ALPHABET[(bits >> (18 - 6 * k) & 63) as usize] as char),
                false => out.push('='),
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if base64 is decoded wrongly at any padding length, or accepts a stray character.
    #[test]
    fn base64_round_trips() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("Zg==").unwrap(), b"f");
        assert_eq!(decode_base64("Zm8=").unwrap(), b"fo");
        assert_eq!(decode_base64("Zm9v").unwrap(), b"foo");
        assert_eq!(decode_base64("Zm9vYg").unwrap(), b"foob");
        assert_eq!(decode_base64("/+8A").unwrap(), [0xff, 0xef, 0x00]);
        assert!(decode_base64("Zm9v!").is_none());
        assert!(decode_base64("Z").is_none());
        let bytes: Vec<u8> = (0..=255).collect();
        for n in 0..bytes.len() {
            assert_eq!(
                decode_base64(&encode_base64(&bytes[..n])).unwrap(),
                &bytes[..n]
            );
        }
    }
}
