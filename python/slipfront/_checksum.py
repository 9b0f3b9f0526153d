"""The checksum block every file slipfront writes begins with (docs/output.md, "Checksum").

A faithful copy of ``apps/h5in.cpp: verify_checksum``: the file is *intact* when its first 512 bytes are
exactly the block the writer (``apps/h5out.cpp: checksum_block``) writes for the bytes after them, so
every byte is covered (a flip in the HDF5 part changes the hash, one in the block's text or padding the
block, truncation or an appended byte both). The hash is XXH3-64: from the ``xxhash`` module when it is
installed (Debian: python3-xxhash), else from the system's libxxhash (the library slipfront itself links)
through ctypes.
"""
import ctypes
import ctypes.util
import mmap

BLOCK_BYTES = 512
MAGIC = b"slipfront results checksum\n"
HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def _xxh3_from_module():
    try:
        import xxhash
    except ImportError:
        return None
    return lambda data: xxhash.xxh3_64_intdigest(data)


def _xxh3_from_library():
    for name in ("libxxhash.so.0", ctypes.util.find_library("xxhash")):
        if not name:
            continue
        try:
            lib = ctypes.CDLL(name)
        except OSError:
            continue
        f = lib.XXH3_64bits
        f.restype = ctypes.c_uint64
        f.argtypes = [ctypes.c_void_p, ctypes.c_size_t]

        def hash_bytes(data, f=f):
            view = memoryview(data)
            if view.nbytes == 0:
                return f(None, 0)
            if view.readonly:  # bytes: ctypes takes them as they are
                return f(ctypes.c_char_p(bytes(view)), view.nbytes)
            buf = (ctypes.c_char * view.nbytes).from_buffer(view)  # no copy (a copy-on-write map)
            try:
                return f(buf, view.nbytes)
            finally:
                del buf
        return hash_bytes
    return None


_hash = _xxh3_from_module() or _xxh3_from_library()


def xxh3_64(data):
    """XXH3-64 of the bytes, as an int (core::content_hash)."""
    if _hash is None:
        raise RuntimeError("no XXH3-64 available to verify the checksum: install the xxhash module "
                           "(python3-xxhash) or the xxHash library (libxxhash0), or open with verify=False")
    return _hash(data)


def checksum_block(payload):
    """The 512-byte block the writer puts before `payload` (apps/h5out.cpp: checksum_block)."""
    text = MAGIC + b"xxh3-64 %016x\nbytes %d\n" % (xxh3_64(payload), len(payload))
    return text.ljust(BLOCK_BYTES, b"\0")


def _field(block, label):
    at = block.find(label)
    if at < 0:
        return ""
    start = at + len(label)
    end = block.find(b"\n", start)
    return block[start:end if end >= 0 else len(block)].decode("ascii", "replace")


def verify(path):
    """("intact" | "absent" | "failed", detail): the verdict of apps/h5in.cpp verify_checksum."""
    with open(path, "rb") as f:
        size = f.seek(0, 2)
        if size == 0:
            return "failed", "damaged: the file begins neither with slipfront's checksum block nor with HDF5's signature"
        with mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_COPY) as m:
            if m[:len(MAGIC)] != MAGIC:
                if m[:len(HDF5_SIGNATURE)] == HDF5_SIGNATURE:
                    return "absent", ("no checksum (an HDF5 file without slipfront's checksum block: written "
                                      "before checksums, or not by slipfront)")
                return "failed", "damaged: the file begins neither with slipfront's checksum block nor with HDF5's signature"
            if size < BLOCK_BYTES:
                return "failed", "truncated: %d bytes, shorter than its checksum block" % size
            block = m[:BLOCK_BYTES]
            payload = memoryview(m)[BLOCK_BYTES:]
            try:
                now = xxh3_64(payload)
                expected = MAGIC + b"xxh3-64 %016x\nbytes %d\n" % (now, len(payload))
                expected = expected.ljust(BLOCK_BYTES, b"\0")
            finally:
                payload.release()
    if block == expected:
        return "intact", ""
    stored, stored_size = _field(block, b"xxh3-64 "), _field(block, b"\nbytes ")
    computed = "%016x" % now
    if stored != computed:
        size_note = "" if stored_size == str(size - BLOCK_BYTES) else " (stored size %s)" % stored_size
        return "failed", ("checksum fails: stored xxh3-64 %s, the %d bytes after the block hash to %s%s"
                          % (stored or "(unreadable)", size - BLOCK_BYTES, computed, size_note))
    return "failed", "checksum block altered (its hash matches the content, its other bytes do not)"
