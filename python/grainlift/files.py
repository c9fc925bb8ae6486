"""Writing files so that a failure leaves the previous one: the figures and pages the scripts
write, as the C++ code writes its results (shared/src/results/atomic_file.cc).

    from grainlift import files
    files.write_atomically("out/report.html", lambda tmp: open(tmp, "w").write(text))

The callback writes a temporary file beside the final one; it is renamed into place only when
the callback returns, and removed when it raises (a full disk: the old file is kept)."""
import errno
import os


def write_atomically(path, write):
    """Calls write(tmp) for a temporary path beside @p path, then renames tmp to @p path."""
    folder, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(folder, f".{name}.tmp.{os.getpid()}")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        if isinstance(e, OSError):  # named by the file the user asked for
            raise OSError(e.errno, e.strerror, path) from e
        raise
    return path


def advice(err):
    """What to do about an OSError @p err of a write, in a few words."""
    if err.errno in (errno.ENOSPC, errno.EDQUOT):
        return "free some space or write elsewhere"
    if err.errno == errno.EROFS:
        return "the file system is read-only: write elsewhere"
    if err.errno in (errno.EACCES, errno.EPERM):
        return "no permission to write there: write elsewhere"
    return "write elsewhere"
