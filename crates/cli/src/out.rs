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

/// No plan, as an answer rather than a fault (no route for the robot): exit 1.
#[derive(Debug)]
pub struct NoPlan(String);

impl std::fmt::Display for NoPlan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for NoPlan {}

/// No plan, as an answer: `msg` and exit 1.
pub fn no_plan(msg: impl Into<String>) -> anyhow::Error {
    NoPlan(msg.into()).into()
}

/// No plan because `plan --time-limit` passed first: exit 4.
#[derive(Debug)]
pub struct TimedOut(pub String);

impl std::fmt::Display for TimedOut {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for TimedOut {}

/// A map error as the command line answers it: no route for the robot is no plan (exit 1),
/// anything else the input's fault (exit 2).
pub fn map_error(e: homospline_maps::MapError) -> anyhow::Error {
    if e.is_no_route() {
        NoPlan(e.to_string()).into()
    } else {
        bad(e.to_string())
    }
}

/// Writes `bytes` to `path` whole or not at all: into a temporary file beside it, then
/// renamed over it. A full disk or a failed write leaves any file already at `path` as it
/// was (no truncated output, no good file destroyed), and the temporary file is removed.
/// What this process's stdout or stderr is (`--json /dev/stdout`, redirected to a file or
/// not) is written through that stream; what is no regular file (`/dev/null`, a named
/// pipe, `>(jq .)`) is written to as it is, never replaced. A file the user may write in a
/// directory where no temporary file can be made is written in place, which is not whole
/// or nothing: the message says so when that write fails.
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
    match special(path) {
        Some(Special::Stdout) => return stdout_write(&String::from_utf8_lossy(bytes)),
        Some(Special::Stderr) => {
            use std::io::Write;
            return std::io::stderr()
                .lock()
                .write_all(bytes)
                .with_context(context);
        }
        Some(Special::Device) => return write_in_place(path, bytes).with_context(context),
        None => {}
    }
    // A link is followed: the file it names is replaced, and the link stays.
    let target = link_target(path);
    let path = target.as_path();
    match write_replacing(path, bytes) {
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied && writable(path) => {
            write_in_place(path, bytes).with_context(|| {
                format!(
                    "{} (written in place, as no temporary file can be made beside it: it may be incomplete)",
                    context()
                )
            })
        }
        r => r.with_context(context),
    }
}

/// An output that is not replaced by a file.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Special {
    /// This process's stdout (the same file, device or pipe).
    Stdout,
    /// This process's stderr.
    Stderr,
    /// A device, pipe or socket.
    Device,
}

/// Whether `path`, links followed, is this process's stdout or stderr, or no regular file
/// and no directory.
fn special(path: &Path) -> Option<Special> {
    let m = path.metadata().ok()?;
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        use std::os::unix::fs::MetadataExt;
        let same = |fd: std::os::fd::BorrowedFd<'_>| {
            fd.try_clone_to_owned()
                .ok()
                .and_then(|fd| std::fs::File::from(fd).metadata().ok())
                .is_some_and(|s| s.dev() == m.dev() && s.ino() == m.ino())
        };
        if same(std::io::stdout().as_fd()) {
            return Some(Special::Stdout);
        }
        if same(std::io::stderr().as_fd()) {
            return Some(Special::Stderr);
        }
    }
    (!m.is_file() && !m.is_dir()).then_some(Special::Device)
}

/// `bytes` into a temporary file beside `path`, renamed over it; the temporary file is
/// removed when that fails, and by [`remove_temporaries_on_signals`]' handler when the
/// process is told to stop meanwhile.
fn write_replacing(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let tmp = temporary(path, "tmp");
    pending().push(tmp.clone());
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        hold_for_signal_test();
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    pending().retain(|p| *p != tmp);
    result
}

/// The temporary files being written, which a signal's handler removes.
static PENDING: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

fn pending() -> std::sync::MutexGuard<'static, Vec<std::path::PathBuf>> {
    PENDING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Folders of this process's own (`serve`'s uploads), which a signal's handler removes.
static PENDING_DIRS: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Removes `dir` and what it holds when the process dies of SIGINT, SIGTERM or SIGHUP.
pub fn remove_dir_on_signals(dir: &Path) {
    PENDING_DIRS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .push(dir.to_owned());
}

/// Test hook: with `HOMOSPLINE_HOLD_WRITE_MS=N`, a write waits `N` ms (at most 10 s) between
/// its temporary file and the rename, so that the signal tests can stop it there.
fn hold_for_signal_test() {
    if let Some(ms) = std::env::var("HOMOSPLINE_HOLD_WRITE_MS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
    {
        std::thread::sleep(std::time::Duration::from_millis(ms.min(10_000)));
    }
}

/// On SIGINT, SIGTERM or SIGHUP: removes the temporary files being written (the outputs
/// themselves are whole, old or new) and the folders of [`remove_dir_on_signals`], then dies of the signal as it would have (the shell
/// sees 130, 143 or 129). Installed once, by `main`; a failure to install is ignored (the
/// signals then act as before: the outputs stay whole, a temporary file may be left).
pub fn remove_temporaries_on_signals() {
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
            return;
        };
        let _ = std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                if let Some(sig) = signals.forever().next() {
                    for tmp in pending().drain(..) {
                        let _ = std::fs::remove_file(tmp);
                    }
                    let dirs = PENDING_DIRS
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                        .drain(..)
                        .collect::<Vec<_>>();
                    for dir in dirs {
                        let _ = std::fs::remove_dir_all(dir);
                    }
                    let _ = signal_hook::low_level::emulate_default_handler(sig);
                    std::process::exit(128 + sig);
                }
            });
    }
}

/// `bytes` written into `path` as it is: over its start, then cut to their length (a
/// device or pipe is not cut).
fn write_in_place(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
    f.write_all(bytes)?;
    if f.metadata()?.is_file() {
        f.set_len(bytes.len() as u64)?;
    }
    Ok(())
}

/// A file beside `path` with the suffix `kind`: `.NAME.PID.KIND`, the name cut to 200
/// bytes so that a long output name still leaves room for it.
fn temporary(path: &Path, kind: &str) -> std::path::PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".to_owned(), |n| n.to_string_lossy().into_owned());
    let mut cut = name.len().min(200);
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    path.with_file_name(format!(".{}.{}.{kind}", &name[..cut], std::process::id()))
}

/// Whether `path` is a regular file this process may write (opened without truncation).
fn writable(path: &Path) -> bool {
    path.metadata().is_ok_and(|m| m.is_file())
        && std::fs::OpenOptions::new().write(true).open(path).is_ok()
}

/// Whether [`write()`] can replace `path` (a link's target): a file can be made beside it,
/// or it is a file the user may write. Makes and removes a probe of its own name (a
/// temporary file a killed run left behind does not stand in the way).
fn can_write(path: &Path) -> std::io::Result<()> {
    let probe = temporary(path, "probe");
    match std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .open(&probe)
    {
        Ok(_) => std::fs::remove_file(&probe),
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

/// Refuses, before any work, an output path that is one of the inputs or another output, a
/// directory, or one that cannot be written (its directory missing or not writable): a plan
/// of minutes ended on a typo, and `--json` equal to the scene overwrote it.
pub fn check_outputs(
    inputs: &[&Path],
    outputs: &[(&str, &str, Option<&Path>)],
) -> anyhow::Result<()> {
    // Outputs need not exist yet: their directory is resolved, and their name joined. A
    // link is followed first, as `write` follows it. Each path is resolved once.
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
    let key = |p: &Path| resolve(p).unwrap_or_else(|| p.to_path_buf());
    let inputs: std::collections::HashMap<std::path::PathBuf, &Path> =
        inputs.iter().rev().map(|&i| (key(i), i)).collect();
    let mut written: std::collections::HashMap<std::path::PathBuf, &str> =
        std::collections::HashMap::new();
    for &(flag, what, p) in outputs {
        let Some(p) = p else { continue };
        let at = key(p);
        if let Some(input) = inputs.get(&at) {
            return Err(bad(format!(
                "{flag} {}: is the input {}; write the output elsewhere",
                p.display(),
                input.display()
            )));
        }
        // Two outputs may share a device or a standard stream (`--json /dev/null --svg
        // /dev/null`), not a file.
        if special(p).is_some() {
            continue;
        }
        if let Some(other) = written.insert(at, flag) {
            return Err(bad(format!(
                "{flag} {}: is also the {other} output; give each output its own file",
                p.display()
            )));
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
