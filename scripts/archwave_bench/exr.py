"""A minimal OpenEXR reader (numpy + zlib): single-part scanline files with NONE, ZIPS or ZIP
compression and HALF, FLOAT or UINT channels, which covers archwave's output (FLOAT, ZIP) and
Blender's (FLOAT, ZIP or NONE). The race section reads images with it to compare them per
region; Debian 12 ships no Python OpenEXR binding for the system interpreter."""

import struct
import zlib

import numpy as np

_PIXEL = {0: (np.uint32, 4), 1: (np.float16, 2), 2: (np.float32, 4)}
_LINES_PER_BLOCK = {0: 1, 2: 1, 3: 16}  # NONE, ZIPS, ZIP


def _attributes(data):
    """{name: (type, bytes)} of the header and the offset just past it."""
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file")
    version = struct.unpack_from("<I", data, 4)[0]
    if version & 0x200 or version & 0x1000:
        raise ValueError("tiled or multi-part EXR files are not supported")
    pos, attrs = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        tend = data.index(b"\0", end + 1)
        typ = data[end + 1:tend].decode()
        size = struct.unpack_from("<i", data, tend + 1)[0]
        attrs[name] = (typ, data[tend + 5:tend + 5 + size])
        pos = tend + 5 + size
    return attrs, pos + 1


def _channels(raw):
    out, pos = [], 0
    while raw[pos] != 0:
        end = raw.index(b"\0", pos)
        name = raw[pos:end].decode()
        ptype, _, _, xs, ys = struct.unpack_from("<iB3sii", raw, end + 1)
        if xs != 1 or ys != 1:
            raise ValueError("subsampled EXR channels are not supported")
        out.append((name, ptype))
        pos = end + 1 + 16
    return out


def _unzip(block, expected):
    """zlib, then OpenEXR's predictor and byte interleaving undone."""
    t = np.frombuffer(zlib.decompress(block), np.uint8).astype(np.int16)
    if t.size != expected:
        raise ValueError("corrupt ZIP block")
    t = (np.cumsum(t - 128, dtype=np.int64) + 128) % 256  # t[i] = t[i-1] + t[i] - 128
    t = t.astype(np.uint8)
    half = (t.size + 1) // 2
    out = np.empty_like(t)
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return out.tobytes()


def read_exr(path, names=("R", "G", "B")):
    """The channels `names` of an EXR as a float32 array (height, width, len(names))."""
    with open(path, "rb") as f:
        data = f.read()
    attrs, pos = _attributes(data)
    chans = _channels(attrs["channels"][1])
    comp = attrs["compression"][1][0]
    if comp not in _LINES_PER_BLOCK:
        raise ValueError(f"{path}: EXR compression {comp} is not supported (NONE, ZIPS, ZIP are)")
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    lines = _LINES_PER_BLOCK[comp]
    nblocks = (h + lines - 1) // lines
    offsets = struct.unpack_from(f"<{nblocks}Q", data, pos)
    planes = {name: np.zeros((h, w), np.float32) for name, _ in chans}
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        n = min(lines, y1 - y + 1)
        row_bytes = sum(_PIXEL[t][1] for _, t in chans) * w
        block = data[off + 8:off + 8 + size]
        if size < row_bytes * n and comp != 0:
            block = _unzip(block, row_bytes * n)
        cursor = 0
        for r in range(n):
            for name, t in chans:  # channels are stored in name order within each line
                dt, sz = _PIXEL[t]
                planes[name][y - y0 + r] = np.frombuffer(block, dt, w, cursor).astype(np.float32)
                cursor += sz * w
    missing = [n for n in names if n not in planes]
    if missing:
        raise ValueError(f"{path}: no channel(s) {', '.join(missing)}")
    return np.stack([planes[n] for n in names], axis=-1)
