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
    // A link is followed: the file it names is replaced, and the link stays.
    let target = link_target(path);
    let path = target.as_path();
    let name = path
        .file_name()
        .map_or_else(|| "output".to_owned(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        use std::io::Write;
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(context)
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
/// or whose directory does not exist: a plan of minutes ended on a typo, and `--json`
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
        if let Some((other, _, _)) = given[..k].iter().find(|(_, _, q)| same(q, p)) {
            return Err(bad(format!(
                "{flag} {}: is also the {other} output; give each output its own file",
                p.display()
            )));
        }
        // Not the input's fault: like a write that fails, exit 3.
        let target = link_target(p);
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
    }
    Ok(())
}
