"""Is an OpenEXR file whole? A cheap check of its header and chunk offsets
before Blender loads it: Blender 3.4 hangs (a busy loop, measured) on a
truncated lookup atlas instead of failing, so Apply checks first and reports
the damaged file.

The layout is the OpenEXR file format's ("OpenEXR File Layout", openexr.com):
magic, version, the header's attributes (name, type, size, value) up to an
empty name, the offset table (one uint64 per chunk), then the chunks. A
scanline chunk is int32 y, int32 size and size bytes; a tiled one has four
int32 tile coordinates before its size. Multi-part and deep files, and
tiled files with more than one level, are passed after the header (clothbake
writes none of them).
"""
import os
import struct

from .errors import ClothbakeError

MAGIC = 20000630
_TILED, _LONG_NAMES, _DEEP, _MULTIPART = 0x200, 0x400, 0x800, 0x1000
# Scanlines per chunk by compression: NONE, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA, DWAB.
_LINES_PER_CHUNK = (1, 1, 1, 16, 32, 16, 32, 32, 32, 256)
_MAX_CHUNKS = 1 << 28


def _damaged(path, what):
    return ClothbakeError(f"the lookup image is damaged or truncated ({what}); bake again", path)


def _cstring(f, path, limit):
    out = bytearray()
    while True:
        c = f.read(1)
        if not c:
            raise _damaged(path, "the header ends early")
        if c == b"\0":
            return out.decode("latin-1")
        out += c
        if len(out) > limit:
            raise _damaged(path, "a header name is too long")


def check_exr(path):
    """Raises ClothbakeError unless `path` is an OpenEXR file whose header
    parses and whose every chunk lies inside the file. Returns the data
    window's (width, height), or None for a file checked no further than its
    header (multi-part, deep, mip-mapped)."""
    try:
        size = os.path.getsize(path)
        with open(path, "rb") as f:
            head = f.read(8)
            if len(head) < 8 or struct.unpack("<i", head[:4])[0] != MAGIC:
                raise ClothbakeError("the lookup image is not an OpenEXR file; bake again", path)
            flags = struct.unpack("<i", head[4:])[0]
            limit = 255 if flags & _LONG_NAMES else 31
            attrs = {}
            while True:
                name = _cstring(f, path, limit)
                if not name:
                    break
                kind = _cstring(f, path, limit)
                (length,) = struct.unpack("<i", f.read(4).ljust(4, b"\0"))
                if length < 0 or f.tell() + length > size:
                    raise _damaged(path, f"attribute '{name}' runs past the end of the file")
                value = f.read(length)
                if name in ("dataWindow", "compression", "tiles"):
                    attrs[name] = (kind, value)
            if flags & (_DEEP | _MULTIPART):
                return None
            if "dataWindow" not in attrs or "compression" not in attrs:
                raise _damaged(path, "no dataWindow or compression in the header")
            x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"][1][:16].ljust(16, b"\0"))
            width, height = x1 - x0 + 1, y1 - y0 + 1
            compression = attrs["compression"][1][:1]
            if width < 1 or height < 1 or not compression or \
                    compression[0] >= len(_LINES_PER_CHUNK):
                raise _damaged(path, "an invalid dataWindow or compression")
            if flags & _TILED:
                if "tiles" not in attrs or len(attrs["tiles"][1]) < 9:
                    raise _damaged(path, "a tiled file without a tiles description")
                tx, ty = struct.unpack("<2I", attrs["tiles"][1][:8])
                if attrs["tiles"][1][8] & 0x0F != 0 or tx < 1 or ty < 1:
                    return None  # mip- or rip-mapped: not checked further
                chunks = -(-width // tx) * -(-height // ty)
                chunk_header = 20
            else:
                chunks = -(-height // _LINES_PER_CHUNK[compression[0]])
                chunk_header = 8
            table_end = f.tell() + 8 * chunks
            if chunks > _MAX_CHUNKS or table_end > size:
                raise _damaged(path, f"the file ends at byte {size}, inside its offset table")
            offsets = struct.unpack(f"<{chunks}Q", f.read(8 * chunks))
            for i, offset in enumerate(offsets):
                if offset < table_end or offset + chunk_header > size:
                    raise _damaged(path, f"chunk {i} starts at byte {offset}, outside the "
                                         f"{size}-byte file")
                f.seek(offset + chunk_header - 4)
                (length,) = struct.unpack("<i", f.read(4))
                if length < 0 or offset + chunk_header + length > size:
                    raise _damaged(path, f"the file ends at byte {size}; chunk {i} needs "
                                         f"{offset + chunk_header + max(length, 0)}")
            return width, height
    except OSError as e:
        raise ClothbakeError(f"cannot read the lookup image: {e.strerror}", path) from None
    except struct.error:
        raise _damaged(path, "the header ends early") from None
