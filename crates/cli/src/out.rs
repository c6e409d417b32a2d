//! What the commands write: lines to stdout (a closed pipe is no error), output files
//! written whole or not at all and checked before the work, and the user's-input error
//! (exit 2) apart from the run's failures (exit 3).

use std::path::Path;

use anyhow::Context;

/// Writes a line to stdout. A closed pipe (`homospline plan | head`) drops the output
/// and the command goes on to its files and its exit code; any other write error fails.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::out::stdout_write(&format!("{}\n", format_args!($($arg)*)))?
    };
}

/// [`say!`] without the line end.
macro_rules! say_raw {
    ($($arg:tt)*) => {
        $crate::out::stdout_write(&format!($($arg)*))?
    };
}

/// Writes `text` to stdout; a closed pipe drops it.
pub fn stdout_write(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::anyhow!("cannot write to stdout: {e}"))
        }
        _ => Ok(()),
    }
}

/// An error that is the user's input: exit 2.
#[derive(Debug)]
pub struct BadInput(String);

impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// The user's input is at fault: `msg` and exit 2.
pub fn bad(msg: impl Into<String>) -> anyhow::Error {
    BadInput(msg.into()).into()
}

/// Writes `bytes` to `path` whole or not at all: into a temporary file beside it, then
/// renamed over it. A full disk or a failed write leaves any file already at `path` as it
/// was (no truncated output, no good file destroyed), and the temporary file is removed.
/// What is no regular file (`/dev/null`, `/dev/stdout`, a named pipe, `>(jq .)`) is
/// written to as it is, never replaced; so is a file the user may write in a directory
/// where no temporary file can be made.
pub fn write(path: &Path, what: &str, bytes: &[u8]) -> anyhow::Result<()> {
    let context = || match path
        .parent()
        .filter(|d| !d.as_os_str().is_empty() && !d.exists())
    {
        Some(d) => format!(
            "{}: cannot write the {what}: the directory {} does not exist",
            path.display(),
            d.display()
        ),
        None => format!("{}: cannot write the {what}", path.display()),
    };
    if is_device(path) {
        return write_in_place(path, bytes, false).with_context(context);
    }
    // A link is followed: the file it names is replaced, and the link stays.
    let target = link_target(path);
    let path = target.as_path();
    let result = match write_replacing(path, bytes) {
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied && writable(path) => {
            write_in_place(path, bytes, true)
        }
        r => r,
    };
    result.with_context(context)
}

/// `bytes` into a temporary file beside `path`, renamed over it; the temporary file is
/// removed when that fails.
fn write_replacing(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let tmp = temporary(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// `bytes` written into `path` as it is (emptied first when `truncate`).
fn write_in_place(path: &Path, bytes: &[u8], truncate: bool) -> std::io::Result<()> {
    use std::io::Write;
    std::fs::OpenOptions::new()
        .write(true)
        .truncate(truncate)
        .open(path)?
        .write_all(bytes)
}

/// The temporary file beside `path` that [`write`] renames over it.
fn temporary(path: &Path) -> std::path::PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".to_owned(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

/// Whether `path` is a regular file this process may write (opened without truncation).
fn writable(path: &Path) -> bool {
    path.metadata().is_ok_and(|m| m.is_file())
        && std::fs::OpenOptions::new().write(true).open(path).is_ok()
}

/// Whether `path`, links followed, is there and is no regular file and no directory: a
/// device, a pipe or a socket, which [`write`] writes to as it is.
fn is_device(path: &Path) -> bool {
    path.metadata().is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Whether [`write`] can replace `path` (a link's target): a temporary file can be made
/// beside it, or it is a file the user may write. Makes and removes the temporary file.
fn can_write(path: &Path) -> std::io::Result<()> {
    let tmp = temporary(path);
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
    {
        Ok(_) => std::fs::remove_file(&tmp),
        Err(_) if writable(path) => Ok(()),
        Err(e) => Err(e),
    }
}

/// The file `path` names, following symbolic links, also those that point to a file not
/// there yet (at most 40 of them, as the kernel); `path` itself when it is no link.
fn link_target(path: &Path) -> std::path::PathBuf {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        let is_link = p
            .symlink_metadata()
            .is_ok_and(|m| m.file_type().is_symlink());
        if !is_link {
            break;
        }
        match std::fs::read_link(&p) {
            Ok(l) if l.is_relative() => p = p.parent().unwrap_or(Path::new(".")).join(l),
            Ok(l) => p = l,
            Err(_) => break,
        }
    }
    p
}

/// Refuses, before any work, an output path that is one of the inputs or another output,
/// a directory, or one that cannot be written (its directory missing or not writable): a plan of minutes ended on a typo, and `--json`
/// equal to the scene overwrote it.
pub fn check_outputs(
    inputs: &[&Path],
    outputs: &[(&str, &str, Option<&Path>)],
) -> anyhow::Result<()> {
    // Outputs need not exist yet: their directory is resolved, and their name joined. A
    // link is followed first, as `write` follows it.
    let resolve = |p: &Path| {
        let p = &link_target(p);
        p.canonicalize().ok().or_else(|| {
            let dir = match p.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            Some(dir.canonicalize().ok()?.join(p.file_name()?))
        })
    };
    let same = |a: &Path, b: &Path| match (resolve(a), resolve(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    };
    let given: Vec<(&str, &str, &Path)> = outputs
        .iter()
        .filter_map(|&(flag, what, p)| p.map(|p| (flag, what, p)))
        .collect();
    for (k, &(flag, what, p)) in given.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|i| same(i, p)) {
            return Err(bad(format!(
                "{flag} {}: is the input {}; write the output elsewhere",
                p.display(),
                input.display()
            )));
        }
        // Two outputs may share a device (`--json /dev/null --svg /dev/null`), not a file.
        let device = is_device(p);
        if let Some((other, _, _)) = given[..k].iter().find(|(_, _, q)| !device && same(q, p)) {
            return Err(bad(format!(
                "{flag} {}: is also the {other} output; give each output its own file",
                p.display()
            )));
        }
        if device {
            continue;
        }
        let target = link_target(p);
        if target.is_dir() {
            return Err(bad(format!(
                "{flag} {}: is a directory; name a file",
                p.display()
            )));
        }
        // Not the input's fault: like a write that fails, exit 3.
        if let Some(d) = target
            .parent()
            .filter(|d| !d.as_os_str().is_empty() && !d.is_dir())
        {
            return Err(anyhow::anyhow!(
                "{}: cannot write the {what}: the directory {} does not exist",
                p.display(),
                d.display()
            ));
        }
        can_write(&target).with_context(|| format!("{}: cannot write the {what}", p.display()))?;
    }
    Ok(())
}
