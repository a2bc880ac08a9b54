"""Reading the files other people may have put in a shared folder: the pages
an index reads, the statistics and tables of a run, a cohort's manifest,
seeds tables and run records. Only a regular file is read, and at most a
bound of bytes: a FIFO named ``report.html`` would block the reader for
ever, and a link to ``/dev/zero`` would be read until memory runs out.

The file is opened without blocking (``O_NONBLOCK``) and checked on the
open descriptor (``fstat``), so that nothing can be swapped in between the
check and the reading; the C++ library does the same for the images and
meshes it reads (``stvd/system/files/regular_file.hpp``)."""

import errno
import os
import stat

# The most bytes read from each kind of file (docs/reliability.md,
# "Security"): far beyond what stvd writes, far below what would exhaust a
# machine's memory.
PAGE_BYTES = 256 << 20        # a QC page (a few MB: its pictures are embedded)
RECORD_BYTES = 64 << 20       # --stats JSON, statistics.json, run.json
TABLE_BYTES = 1 << 30         # connectivity and path tables, VTK paths (1,000 regions: 60 MB)
MANIFEST_BYTES = 256 << 20    # a manifest or a seeds table


class NotARegularFileError(OSError):
    """A file that is not read: not a regular file, too large, or not
    readable. ``str()`` is one line, "<path>: <reason>"."""

    def __init__(self, path, reason, code=errno.EINVAL):
        super().__init__(code, reason, os.fspath(path))
        self.reason = reason

    def __str__(self):
        return f"{self.filename}: {self.reason}"


def kind_of(mode):
    """'a FIFO', 'a character device', ... for messages."""
    for test, name in ((stat.S_ISREG, "a regular file"), (stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def _open_regular(path):
    """A descriptor of the regular file ``path`` (links followed), opened
    without blocking and made blocking again, and its status."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    except OSError as error:
        reason = "no such file" if error.errno == errno.ENOENT else f"cannot open: {error.strerror}"
        raise NotARegularFileError(path, reason, error.errno) from None
    try:
        status = os.fstat(fd)
        if not stat.S_ISREG(status.st_mode):
            raise NotARegularFileError(path, f"is {kind_of(status.st_mode)}, not a regular file")
        os.set_blocking(fd, True)
    except BaseException:
        os.close(fd)
        raise
    return fd, status


def require_regular_file(path):
    """NotARegularFileError unless ``path`` is a regular file that can be
    opened: for files a library opens itself afterwards (NiBabel). It never
    blocks; a file swapped for a FIFO between this check and the library's
    own opening is not caught (the library opens by name)."""
    fd, _ = _open_regular(path)
    os.close(fd)


def read_regular_file(path, limit):
    """The bytes of the regular file ``path``; NotARegularFileError when it
    is not one, cannot be read, or holds more than ``limit`` bytes (at most
    ``limit`` + 1 bytes are read, whatever its size says)."""
    fd, status = _open_regular(path)
    try:
        if status.st_size > limit:
            raise NotARegularFileError(path, f"is larger than {limit} bytes ({status.st_size}), more than stvd reads "
                                             "from such a file", errno.EFBIG)
        chunks, total = [], 0
        while total <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
        if total > limit:
            raise NotARegularFileError(path, f"is larger than {limit} bytes, more than stvd reads from such a file",
                                       errno.EFBIG)
        return b"".join(chunks)
    except OSError as error:
        if isinstance(error, NotARegularFileError):
            raise
        raise NotARegularFileError(path, f"cannot read: {error.strerror}", error.errno) from None
    finally:
        os.close(fd)


def read_regular_text(path, limit, encoding="utf-8"):
    """``read_regular_file`` decoded (UnicodeDecodeError when it is not
    ``encoding``)."""
    return read_regular_file(path, limit).decode(encoding)


def open_regular_binary(path):
    """A binary file object of the regular file ``path`` (for hashing a
    large output block by block)."""
    fd, _ = _open_regular(path)
    return os.fdopen(fd, "rb")
