//! Files the program writes, written so that nothing is left half-way: a temporary file in the same
//! folder, made durable, then renamed into place. Used by screenshots and `make-assets`. And the
//! files the scenes read, through [`read`], which the browser page serves from memory.

use std::fs;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::{Error, Result};

/// Distinguishes temporary files of concurrent writers in the same process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes a file atomically: `write` fills a temporary file in the same folder, which is made
/// durable and then renamed over `path`, so a reader (or a crash) never sees a half-written file.
/// On failure nothing is left behind.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<fs::File>) -> Result<()>,
) -> Result<()> {
    let Some(file_name) = path.file_name() else {
        return Err(Error::Write {
            path: path.to_path_buf(),
            reason: "not a file name".into(),
        });
    };
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let temp = folder.join(format!(
        ".{}.{}-{}.tmp",
        file_name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let file = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| Error::io(path, e))?;
    let mut out = BufWriter::new(file);
    let written = write(&mut out)
        .and_then(|()| out.flush().map_err(|e| Error::io(path, e)))
        .and_then(|()| out.get_ref().sync_all().map_err(|e| Error::io(path, e)))
        .and_then(|()| fs::rename(&temp, path).map_err(|e| Error::io(path, e)));
    if written.is_err() {
        let _ = fs::remove_file(&temp);
    }
    written
}

/// Writes `bytes` to `path` atomically (see [`write_atomically`]).
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |out| {
        out.write_all(bytes).map_err(|e| Error::io(path, e))
    })
}

/// Refuses an output file before anything is made for it: `format` reads its format from the name
/// (each tool writes its own formats), and its folder must be there (nothing creates it behind the
/// user's back). The error line starts with `flag` and the file, as typed.
pub fn check_output<F>(
    flag: &str,
    path: &Path,
    format: impl FnOnce(&Path) -> Result<F>,
) -> Result<F> {
    let format = format(path)?;
    let folder = path.parent().filter(|f| !f.as_os_str().is_empty());
    if let Some(folder) = folder.filter(|f| !f.is_dir()) {
        return Err(Error::Argument(format!(
            "{flag} {}: no such folder {} (create it first)",
            path.display(),
            folder.display()
        )));
    }
    Ok(format)
}

/// Reads a file the scenes load (a model, a map, a texture). Natively `std::fs::read`; in the
/// browser, which has no file system, the bytes the page fetched or the learner dropped
/// (`provide`, in a wasm32 build), under the same relative paths.
pub fn read(path: &Path) -> std::io::Result<Vec<u8>> {
    #[cfg(unix)]
    return read_on_threads(path);
    #[cfg(all(not(unix), not(target_arch = "wasm32")))]
    return fs::read(path);
    #[cfg(target_arch = "wasm32")]
    return page::read(path);
}

/// Files at least this large are read a piece per core (a sculpt's OBJ of 100 MB and more).
#[cfg(unix)]
const READ_ON_THREADS_FROM: u64 = 16 << 20;

/// `fs::read`, with a large file read a piece per core: copying 134 MB out of the page cache (and
/// the faults of a fresh buffer) took 0.09 s on one core while the other waited. The buffer comes
/// zeroed from the system (`calloc`), untouched, so that each thread faults in its own piece. Any
/// trouble (a file that shrank while read, an error) reads it again with `fs::read`, whose error is
/// the one reported; bytes appended while it was read are read after, as `fs::read` would.
#[cfg(unix)]
fn read_on_threads(path: &Path) -> std::io::Result<Vec<u8>> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    read_in_pieces(path, READ_ON_THREADS_FROM, cores)
}

/// [`read_on_threads`] of a file of at least `from` bytes, in `cores` pieces.
#[cfg(unix)]
fn read_in_pieces(path: &Path, from: u64, cores: usize) -> std::io::Result<Vec<u8>> {
    use std::io::{Read, Seek, SeekFrom};
    use std::os::unix::fs::FileExt;
    let mut file = fs::File::open(path)?;
    let len = file.metadata()?.len();
    if cores < 2 || len < from {
        return fs::read(path);
    }
    let Ok(size) = usize::try_from(len) else {
        return fs::read(path);
    };
    let mut bytes = vec![0u8; size];
    let piece = size.div_ceil(cores).max(1);
    let read = std::thread::scope(|scope| {
        let file = &file;
        let threads: Vec<_> = (bytes.chunks_mut(piece).enumerate())
            .map(|(k, part)| scope.spawn(move || file.read_exact_at(part, (k * piece) as u64)))
            .collect();
        threads.into_iter().all(|t| matches!(t.join(), Ok(Ok(()))))
    });
    let rest = read
        .then(|| file.seek(SeekFrom::Start(len)))
        .and_then(Result::ok)
        .and_then(|_| file.read_to_end(&mut bytes).ok());
    match rest {
        Some(_) => Ok(bytes),
        None => fs::read(path),
    }
}

/// Whether [`read`] would find a file at `path` (`Path::is_file` natively).
pub fn is_file(path: &Path) -> bool {
    #[cfg(not(target_arch = "wasm32"))]
    return path.is_file();
    #[cfg(target_arch = "wasm32")]
    return page::read(path).is_ok();
}

/// `Path::try_exists` natively; in the browser, whether the page holds the file.
pub fn try_exists(path: &Path) -> std::io::Result<bool> {
    #[cfg(not(target_arch = "wasm32"))]
    return path.try_exists();
    #[cfg(target_arch = "wasm32")]
    return Ok(page::read(path).is_ok());
}

/// Gives [`read`] a file's bytes in the browser: the crate's assets the page fetched, and files a
/// learner dropped on it.
#[cfg(target_arch = "wasm32")]
pub fn provide(path: &Path, bytes: Vec<u8>) {
    page::FILES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .get_or_insert_with(Default::default)
        .insert(path.to_path_buf(), std::sync::Arc::new(bytes));
}

#[cfg(target_arch = "wasm32")]
mod page {
    use std::collections::HashMap;
    use std::path::{Path, PathBuf};
    use std::sync::{Arc, Mutex, PoisonError};

    /// The page's files by path (one thread: the lock is never contended).
    pub(super) static FILES: Mutex<Option<HashMap<PathBuf, Arc<Vec<u8>>>>> = Mutex::new(None);

    pub(super) fn read(path: &Path) -> std::io::Result<Vec<u8>> {
        let files = FILES.lock().unwrap_or_else(PoisonError::into_inner);
        files
            .as_ref()
            .and_then(|files| files.get(path))
            .map(|bytes| bytes.to_vec())
            // In the words Linux uses, which the native program's messages carry.
            .ok_or_else(|| {
                std::io::Error::new(std::io::ErrorKind::NotFound, "No such file or directory")
            })
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// Fails if a file read in pieces is not the bytes `fs::read` reads (a piece at the wrong
    /// offset, one left out, the last one cut short), at sizes that do not divide by the number
    /// of pieces, or if a missing file gives another error.
    #[test]
    fn a_file_read_in_pieces_is_the_file() {
        let dir = std::env::temp_dir().join(format!("files-unit-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        for size in [0usize, 1, 7, 65_536, 1_000_003] {
            // Bytes that differ from their neighbours (a hash of the offset).
            let bytes: Vec<u8> = (0..size as u64)
                .map(|i| (i.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 56) as u8)
                .collect();
            let path = dir.join(format!("{size}.bin"));
            fs::write(&path, &bytes).unwrap();
            for pieces in [1, 2, 3, 5, 16] {
                let read = read_in_pieces(&path, 0, pieces).unwrap();
                assert!(read == bytes, "{size} bytes in {pieces} pieces");
            }
        }
        let missing = read_in_pieces(&dir.join("missing.bin"), 0, 2).unwrap_err();
        assert_eq!(missing.kind(), std::io::ErrorKind::NotFound);
        fs::remove_dir_all(&dir).unwrap();
    }
}
