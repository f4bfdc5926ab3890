"""The cache of generated artefacts, shared by both backends: only what lagcli built runs.

`$XDG_CACHE_HOME/lagcli/<key>/` (default `~/.cache/lagcli`). The key is a SHA-256
of the spec file's bytes and name, the lagcli version, a variant (the C compiler's
`--version` line for a compiled driver, `python-module` for the generated Python
module) and a fingerprint (size, mtime) of lagcli's own source and templates — so
an edited spec, another compiler or another lagcli never reuses a stale entry.
Parameters and the initial state are *not* in the key: both backends take them at
run time.

Why a cached file can be trusted (anyone who can read the spec can compute its key,
so the key is no secret):

1. The root is a directory owned by the current user that nobody else can write
   (mode 0700; every parent owned by the user or root and not writable by others
   unless sticky, as /tmp). Otherwise it is not used at all: builds go to a private
   temporary directory removed at exit (`active_root`).
2. Every entry is a directory of mode 0700 whose files are 0600 (0700 for the
   driver), all owned by the user, created in a private work directory and renamed
   into place once complete (`new_entry`, `publish`).
3. `manifest.json` in the entry records the SHA-256 of every other file. It is
   checked before anything of the entry is used (`load`): it detects damage
   (truncation, a killed writer, a hand edit). It is no defence on its own — whoever
   can write the entry can rewrite the manifest — which is why 1 and 2 are checked
   on every load: together they leave only the user (and root) able to write.
4. The bytes that are checked are the bytes that run: the Python module is
   compiled from the verified bytes in memory; the driver is executed through
   `/proc/<pid>/fd/<n>` of the very descriptor its hash was computed from, so a file
   swapped in after the check is not the one run.

Anything unexpected makes `load` return None with a one-line note (a `RunNote` warning: the CLI
shows it unless --quiet), and
the entry is removed so the caller's rebuild replaces it.

`lagcli cache info/clear` are in `lagcli.run.cache_admin`. This module imports
neither sympy nor numpy (the warm C path uses it).
"""
from __future__ import annotations

import atexit
import contextlib
import hashlib
import json
import os
import re
import shutil
import signal
import stat
import warnings
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

from lagcli.errors import RunNote
from lagcli.version import __version__

MANIFEST = "manifest.json"
_SOURCE_ROOTS = (Path(__file__).resolve().parents[1], Path(__file__).resolve().parents[2] / "templates")
ENTRY_NAME = re.compile(r"[0-9a-f]{32}")
LEFTOVER_NAME = re.compile(r"\.[0-9a-f]{32}\..+")        # work and set-aside directories
_PRIVATE = 0o077                                          # no permission bit for group or others
_READ_FLAGS = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
_noted: set[str] = set()
_fallback: list[Path] = []


def cache_root() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "lagcli"


def cache_key(spec_path: str, spec_bytes: bytes, variant: str) -> str:
    return digest(spec_bytes, Path(spec_path).name.encode(), __version__.encode(),
                  variant.encode(), source_fingerprint().encode())


def digest(*parts: bytes) -> str:
    """An entry's name: the SHA-256 of `parts`, each prefixed by its length (no two lists of
    parts give the same bytes), cut to 32 hex digits (`ENTRY_NAME`)."""
    sha = hashlib.sha256()
    for part in parts:
        sha.update(len(part).to_bytes(8, "little"))
        sha.update(part)
    return sha.hexdigest()[:32]


def source_fingerprint() -> str:
    """Size and mtime of every lagcli source file and template (cheap: stat only)."""
    items = []
    for root in _SOURCE_ROOTS:
        for folder, dirs, files in os.walk(root):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            for name in sorted(files):
                if name.endswith((".py", ".jinja", ".c", ".h")):   # .c, .h: the C runtime
                    st = os.stat(os.path.join(folder, name))
                    items.append(f"{name}:{st.st_size}:{st.st_mtime_ns}")
    return ";".join(items)


def note(text: str, once: bool = False) -> None:
    """A one-line remark, as a `RunNote` (the CLI shows it unless --quiet); `once`: once
    per process (a run checks the root up to three times: warm lookup, cold lookup, build)."""
    if once and text in _noted:
        return
    _noted.add(text)
    warnings.warn(RunNote(f"lagcli: {text}"), stacklevel=2)


# --- the root ---------------------------------------------------------------------

def root_problem(root: Path, create: bool = True) -> str | None:
    """Why `root` must not be used (None: it is safe). `create`: make it (mode 0700) if missing."""
    try:
        if create and not os.path.lexists(root):
            root.parent.mkdir(parents=True, exist_ok=True)
            with contextlib.suppress(FileExistsError):
                os.mkdir(root, 0o700)
        real = os.path.realpath(root)
        st, link = os.stat(real), os.lstat(root)
    except FileNotFoundError:
        return None if not create else "it cannot be created"
    except OSError as exc:
        return f"it cannot be created or read ({exc.strerror})"
    problem = (_directory_problem(st) or _link_problem(link)
               or _parents_problem(Path(os.path.abspath(root))) or _parents_problem(Path(real)))
    if problem is None and not os.access(real, os.W_OK | os.X_OK):
        problem = "it is not writable"
    if problem is None and stat.S_IMODE(st.st_mode) & _PRIVATE:
        with contextlib.suppress(OSError):
            os.chmod(real, 0o700)                 # ours: others need not even read it
    return problem


def _directory_problem(st: os.stat_result) -> str | None:
    if not stat.S_ISDIR(st.st_mode):
        return "it is not a directory"
    if st.st_uid != os.geteuid():
        return f"it belongs to another user (uid {st.st_uid})"
    if st.st_mode & 0o022:
        return f"other users can write to it (mode {stat.S_IMODE(st.st_mode):04o})"
    return None


def _link_problem(link: os.stat_result) -> str | None:
    if stat.S_ISLNK(link.st_mode) and link.st_uid != os.geteuid():
        return f"it is a symlink of another user (uid {link.st_uid})"
    return None


def existing_parents_problem(root: Path) -> str | None:
    """`root_problem`'s test of the directories above `root`, those that exist: asked before
    making a root where a problem would leave it unused (`root_problem` makes it first)."""
    path = Path(os.path.abspath(root))
    while not os.path.lexists(path.parent) and path.parent != path:
        path = path.parent
    return _parents_problem(path)


def _parents_problem(path: Path) -> str | None:
    """Whoever can write a parent can swap the root itself (sticky directories excepted)."""
    for parent in path.parents:
        st = os.stat(parent)
        if st.st_uid not in (0, os.geteuid()):
            return f"its parent {parent} belongs to another user (uid {st.st_uid})"
        if st.st_mode & 0o022 and not st.st_mode & stat.S_ISVTX:
            return f"its parent {parent} is writable by other users"
    return None


def active_root() -> Path:
    """The cache root when it is safe to use, else a private temporary directory (with a note)."""
    root = cache_root()
    problem = root_problem(root)
    if problem is None:
        return root
    note(f"not using the cache directory {root}: {problem}; building in a private "
         "temporary directory instead (removed at exit)", once=True)
    return _fallback_root()


def _fallback_root() -> Path:
    if not _fallback:
        _fallback.append(Path(tempfile.mkdtemp(prefix="lagcli-cache-")))
        atexit.register(_remove_fallback)
    return _fallback[0]


def _remove_fallback() -> None:
    for path in _fallback:
        shutil.rmtree(path, ignore_errors=True)


# --- reading an entry ---------------------------------------------------------------

class DamagedEntry(Exception):
    """Raised by `read_entry` for an entry that failed a check; the message says which."""


@dataclass(frozen=True)
class Entry:
    """A verified entry: `contents` are the checked bytes of every file (manifest aside);
    `program` is what to execute for the file named as executable (None if none)."""

    directory: Path
    contents: dict[str, bytes]
    program: str | None = None
    label: str = ""


def load(key: str, executable: str | None = None, root: Path | None = None) -> Entry | None:
    """The entry `key` after every check, or None: missing, or damaged (then noted on
    stderr and removed, so that the caller rebuilds it). `root`: a root of another kind of
    entry, checked by its caller (`root_problem`), in place of the active one."""
    try:
        directory = (root or active_root()) / key
    except OSError:                           # no usable root, not even a temporary one
        return None
    try:
        return read_entry(directory, key, executable)
    except FileNotFoundError:
        return None
    except (DamagedEntry, OSError) as exc:
        note(f"cache entry {directory} failed its integrity check ({_reason(exc)}); rebuilding it")
        discard(directory)
        return None


def _reason(exc: Exception) -> str:
    return exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)


def read_entry(directory: Path, key: str, executable: str | None) -> Entry:
    """Entry `key` at `directory`, every check passed (else DamagedEntry or OSError).
    Everything is read through descriptors opened without following symlinks."""
    folder = os.open(directory, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
    kept = None                                     # the executable's descriptor
    try:
        _check_private(os.fstat(folder), "the entry directory", stat.S_ISDIR)
        expected, label = _manifest(folder, key)
        present = set(os.listdir(folder)) - {MANIFEST}
        if present != set(expected):
            raise DamagedEntry(f"files {sorted(present ^ set(expected))} missing or unexpected")
        if executable is not None and executable not in expected:
            raise DamagedEntry(f"no {executable}")
        contents = {}
        for name in sorted(expected):
            descriptor = os.open(name, _READ_FLAGS, dir_fd=folder)
            if name == executable:
                kept = descriptor                   # closed below unless handed to `program`
                contents[name] = _checked_bytes(descriptor, name, expected[name])
                continue
            try:
                contents[name] = _checked_bytes(descriptor, name, expected[name])
            finally:
                os.close(descriptor)
        program = _program(kept, directory / executable) if executable is not None else None
        kept = None                                 # handed over to `program`
    finally:
        os.close(folder)
        if kept is not None:
            os.close(kept)
    return Entry(directory, contents, program, label)


def _manifest(folder: int, key: str) -> tuple[dict[str, str], str]:
    """The recorded {file name: SHA-256} of an entry, and its label."""
    try:
        descriptor = os.open(MANIFEST, _READ_FLAGS, dir_fd=folder)
    except FileNotFoundError:
        raise DamagedEntry(f"no {MANIFEST}") from None
    try:
        manifest = json.loads(_checked_bytes(descriptor, MANIFEST))
    except (ValueError, UnicodeDecodeError):
        raise DamagedEntry(f"{MANIFEST} is not valid JSON") from None
    finally:
        os.close(descriptor)
    if not isinstance(manifest, dict) or manifest.get("lagcli") != __version__ or manifest.get("key") != key:
        raise DamagedEntry(f"{MANIFEST} is for another lagcli version or key")
    files = manifest.get("files")
    if not isinstance(files, dict) or not all(isinstance(v, str) for v in files.values()):
        raise DamagedEntry(f"{MANIFEST} has no valid 'files'")
    return files, str(manifest.get("label", ""))


def _checked_bytes(descriptor: int, name: str, sha256: str | None = None) -> bytes:
    """The content of a private regular file of the user, checked against `sha256` if given."""
    _check_private(os.fstat(descriptor), name, stat.S_ISREG)
    with os.fdopen(os.dup(descriptor), "rb") as handle:
        data = handle.read()
    if sha256 is not None and hashlib.sha256(data).hexdigest() != sha256:
        raise DamagedEntry(f"{name}: its content differs from its recorded SHA-256")
    return data


def _check_private(st: os.stat_result, what: str, is_kind) -> None:
    if not is_kind(st.st_mode):
        raise DamagedEntry(f"{what} is of the wrong kind")
    if st.st_uid != os.geteuid():
        raise DamagedEntry(f"{what} belongs to another user (uid {st.st_uid})")
    if stat.S_IMODE(st.st_mode) & _PRIVATE:
        raise DamagedEntry(f"{what} has mode {stat.S_IMODE(st.st_mode):04o}, not private to its owner")


def _program(descriptor: int, path: Path) -> str:
    """How to execute the file open on `descriptor`: through /proc, so that exactly the
    checked file runs, or (no /proc) by its path, which steps 1-2 of the module
    docstring keep to the user's own writes. The descriptor lives as long as the process."""
    through = f"/proc/{os.getpid()}/fd/{descriptor}"
    try:
        same = os.stat(through).st_ino == os.fstat(descriptor).st_ino
    except OSError:
        same = False
    if same:
        return through
    os.close(descriptor)
    return str(path)


def discard(directory: Path) -> None:
    """Remove a damaged entry: set it aside first, so that the rebuilt one can take its name."""
    aside = directory.parent / f".{directory.name}.old-{os.getpid()}-{threading.get_ident()}"
    with contextlib.suppress(OSError):
        os.rename(directory, aside)
        if os.path.isdir(aside) and not os.path.islink(aside):
            shutil.rmtree(aside, ignore_errors=True)
        else:
            os.unlink(aside)


# --- writing an entry ---------------------------------------------------------------

@contextlib.contextmanager
def new_entry(key: str, root: Path | None = None):
    """A private work directory for entry `key` (yielded), removed whatever happens:
    on an exception, on Ctrl-C, and on SIGTERM/SIGHUP (the process then still dies by
    that signal). Fill it, then `publish` it from inside the `with`. Raises OSError
    when it cannot be made. `root` as in `load`."""
    try:
        with _signals_as_exceptions():
            work = (root or active_root()) / f".{key}.{os.urandom(6).hex()}"   # named before it exists,
            try:                                                   # so no signal can orphan it
                os.mkdir(work, 0o700)
                yield work
            finally:
                shutil.rmtree(work, ignore_errors=True)   # already gone when published
    except _Terminated as stop:
        _die_by(stop.signum)


def publish(work: Path, key: str, label: str, executable: str | None = None) -> Entry:
    """Make the files in `work` private, record their SHA-256 in the manifest and rename
    `work` to the entry `key` beside it (atomic: readers see all of it or nothing).
    Returns the entry as `load` reads it. Raises OSError when it cannot be stored."""
    names = sorted(os.listdir(work))
    for name in names:
        os.chmod(work / name, 0o700 if name == executable else 0o600)
    manifest = {"lagcli": __version__, "key": key, "label": label,
                "files": {name: hashlib.sha256((work / name).read_bytes()).hexdigest() for name in names}}
    descriptor = os.open(work / MANIFEST, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(descriptor, "w") as handle:
        json.dump(manifest, handle, indent=1)
    os.chmod(work, 0o700)
    target = work.parent / key
    for attempt in range(2):               # a concurrent run may publish between the two steps
        if os.path.lexists(target):
            discard(target)
        try:
            os.rename(work, target)
            break
        except OSError:
            if attempt:
                raise
    try:
        return read_entry(target, key, executable)
    except DamagedEntry as exc:
        raise OSError(f"the new cache entry {target} cannot be read back: {exc}") from None


class _Terminated(BaseException):
    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


@contextlib.contextmanager
def _signals_as_exceptions():
    """SIGTERM and SIGHUP raise `_Terminated` meanwhile, so that cleanups run (SIGINT
    raises KeyboardInterrupt anyway). Handlers someone else installed are kept."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    for signum in (signal.SIGTERM, getattr(signal, "SIGHUP", None)):
        if signum is not None and signal.getsignal(signum) == signal.SIG_DFL:
            previous[signum] = signal.signal(signum, _raise_terminated)
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


def _raise_terminated(signum, frame):
    raise _Terminated(signum)


def _die_by(signum: int) -> None:
    """End the process by `signum`, as it would have without the cleanup."""
    _remove_fallback()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)
    raise KeyboardInterrupt                # not reached: the default action ends the process

