//! Output files: never over an input, and written atomically (a temporary file beside the
//! output, `tempfile`'s, persisted when whole), or to standard output, where a closed pipe is not an error.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::Context;
use tempfile::TempPath;

/// Refuses to write any of `outputs` over one of `inputs` (motion specs, model or other files
/// given on the same command line): `qgait fk x.mot -o x.mot` would destroy its own input.
/// Paths that do not exist yet (and `builtin:` specs) cannot be the same file as an input.
/// Also refuses one file given as two outputs (`export --trc x --sto x`): the second would
/// replace the first.
pub(crate) fn refuse_overwrite<'a>(
    outputs: impl IntoIterator<Item = &'a Path>,
    inputs: &[impl AsRef<str>],
) -> anyhow::Result<()> {
    let outputs: Vec<&Path> = outputs.into_iter().collect();
    let identities: Vec<Option<PathBuf>> = outputs.iter().map(|o| file_identity(o)).collect();
    for (i, a) in identities.iter().enumerate() {
        let same = identities[i + 1..].iter().any(|b| a.is_some() && a == b);
        if same {
            anyhow::bail!(
                "{}: given as two outputs; the second would replace the first",
                outputs[i].display()
            );
        }
    }
    for out in outputs {
        let Ok(out_real) = out.canonicalize() else {
            continue;
        };
        for input in inputs.iter().map(AsRef::as_ref) {
            if Path::new(input).canonicalize().is_ok_and(|i| i == out_real) {
                anyhow::bail!(
                    "{}: this output is also an input ({input}); refusing to overwrite it",
                    out.display()
                );
            }
        }
    }
    Ok(())
}

/// Where `path` is, whether or not it exists yet: its canonical form, or its directory's with
/// its name, or (a directory still to be made) the path made absolute. `None` for a file that
/// is not a regular one (`/dev/null`, a pipe: written directly, any number of times).
fn file_identity(path: &Path) -> Option<PathBuf> {
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        return None;
    }
    if let Ok(real) = path.canonicalize() {
        return Some(real);
    }
    let name = path.file_name()?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match dir.canonicalize() {
        Ok(dir) => Some(dir.join(name)),
        Err(_) => std::path::absolute(path).ok(),
    }
}

/// A file being written: rows go to a temporary file beside it ([`tempfile`]), persisted as
/// `path` by [`OutputFile::commit`], so that an error half way (a bad row deep in a long motion)
/// leaves no truncated output behind and an earlier file of that name untouched; dropped
/// uncommitted, the temporary file is removed.
/// A path that is not a regular file (`/dev/null`, a named pipe) is written directly.
pub(crate) struct OutputFile {
    path: PathBuf,
    temp: Option<TempPath>,
    out: Option<BufWriter<File>>,
}

impl OutputFile {
    /// Creates the temporary file for `path`.
    pub(crate) fn create(path: &Path) -> anyhow::Result<Self> {
        let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file());
        let cannot = || format!("{}: cannot create", path.display());
        let (file, temp) = if special {
            (File::create(path).with_context(cannot)?, None)
        } else {
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let dir = match path.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            let prefix = format!(".{name}.");
            let mut builder = tempfile::Builder::new();
            builder.prefix(&prefix).suffix(".qgait-partial");
            // As `File::create`: read and write for all, less the umask (a temporary file
            // is otherwise the owner's only).
            #[cfg(unix)]
            builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
            let (file, temp) = builder.tempfile_in(dir).with_context(cannot)?.into_parts();
            (file, Some(temp))
        };
        Ok(Self {
            path: path.to_path_buf(),
            temp,
            out: Some(BufWriter::with_capacity(1 << 16, file)),
        })
    }

    /// The writer.
    pub(crate) fn writer(&mut self) -> &mut BufWriter<File> {
        self.out.as_mut().expect("not committed")
    }

    /// The file's path, for messages.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes the file and persists the temporary file as the final path.
    pub(crate) fn commit(mut self) -> anyhow::Result<()> {
        let out = self.out.take().expect("committed once");
        out.into_inner()
            .map_err(|e| e.into_error())
            .with_context(|| format!("{}: cannot write", self.path.display()))?;
        match self.temp.take() {
            Some(temp) => temp
                .persist(&self.path)
                .map_err(|e| e.error)
                .with_context(|| format!("{}: cannot write", self.path.display())),
            None => Ok(()),
        }
    }
}

/// Runs `body` on a file (written through an [`OutputFile`]) or on stdout when `path` is
/// `None`. A closed stdout pipe (e.g. `| head`) ends the body without an error.
pub(crate) fn write_output_with(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Write) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    match path {
        Some(p) => {
            let mut file = OutputFile::create(p)?;
            body(file.writer()).map_err(|e| with_path(e, p))?;
            file.commit()
        }
        None => {
            let stdout = io::stdout();
            let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
            let result = match body(&mut out) {
                Ok(()) => out.flush().map_err(anyhow::Error::from),
                Err(e) => {
                    // What is still buffered is not passed on: a short motion with an error
                    // leaves standard output empty (a long one has passed on its first rows).
                    let _ = out.into_parts();
                    Err(e)
                }
            };
            match result {
                Err(e) if is_broken_pipe(&e) => Ok(()),
                Err(e) if e.downcast_ref::<io::Error>().is_some() => {
                    Err(e.context("cannot write to standard output"))
                }
                other => other,
            }
        }
    }
}

/// An I/O error of writing `path` gets the path in front; other errors are the input's own.
pub(crate) fn with_path(e: anyhow::Error, path: &Path) -> anyhow::Error {
    if e.downcast_ref::<io::Error>().is_some() {
        e.context(format!("{}: cannot write", path.display()))
    } else {
        e
    }
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.downcast_ref::<io::Error>()
        .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe)
}

/// Writes to a file, or to stdout when `path` is `None`. A closed stdout pipe (e.g. `| head`) is
/// not an error.
pub(crate) fn write_output(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> anyhow::Result<()> {
    match path {
        Some(p) => {
            let file =
                File::create(p).with_context(|| format!("{}: cannot create", p.display()))?;
            let mut out = BufWriter::new(file);
            body(&mut out)
                .and_then(|_| out.flush())
                .with_context(|| format!("{}: cannot write", p.display()))
        }
        None => {
            let stdout = io::stdout();
            let mut out = BufWriter::new(stdout.lock());
            match body(&mut out).and_then(|_| out.flush()) {
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
                other => other.context("cannot write to standard output"),
            }
        }
    }
}
