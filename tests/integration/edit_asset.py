"""Makes hostile but correctly sealed deepsea assets for the bad-input tests: same-length edits
of an asset's bytes, then the integrity record recomputed as docs/asset-format.md describes it
(an independent implementation of the scheme: if the two disagree, every edited file is refused
for its hash instead of for what the edit broke, and the test notices).

usage: edit_asset.py IN OUT EDIT   EDIT: flip:OFFSET | reseal | no-backscatter | bad-json |
       negative-attenuation | zero-lamps | legacy
"""
import hashlib
import re
import struct
import sys

KEY = b"deepsea:integrity"
SIG = (struct.pack("<I", len(KEY)) + KEY + struct.pack("<I", 6) + b"string" +
       struct.pack("<I", 93) + b"size=")


def seal(data: bytearray) -> None:
    at = data.find(SIG)
    assert 0 <= at < (1 << 20), "no integrity record"
    size = at + len(SIG)
    sha = size + 16 + len(b" sha256=")
    data[size:size + 16] = b"0" * 16
    data[sha:sha + 64] = b"0" * 64
    digest = hashlib.sha256(data).hexdigest().encode()
    data[size:size + 16] = b"%016d" % len(data)
    data[sha:sha + 64] = digest


def same_length(old: bytes, new: bytes) -> bytes:
    assert len(new) <= len(old), (old, new)
    return new + b" " * (len(old) - len(new))  # JSON allows the padding


def edit_json(data: bytearray, fn) -> None:
    """Applies fn to every copy of the deepsea:bake JSON (file and grid metadata)."""
    text = bytes(data)
    out = bytearray()
    pos = 0
    entry = b"deepsea:bake" + struct.pack("<I", 6) + b"string"
    for m in re.finditer(re.escape(entry), text):
        start = m.end() + 4  # after the value's length
        length = struct.unpack("<I", text[m.end():start])[0]
        j = text[start:start + length]
        nj = fn(j)
        assert len(nj) == len(j)
        out += text[pos:start] + nj
        pos = start + length
    assert pos > 0, "no deepsea:bake JSON found"
    out += text[pos:]
    data[:] = out


def brackets(j: bytes, start: int) -> int:
    depth = 0
    for i in range(start, len(j)):
        depth += {ord("["): 1, ord("{"): 1, ord("]"): -1, ord("}"): -1}.get(j[i], 0)
        if depth == 0:
            return i
    raise ValueError("unbalanced")


def main() -> None:
    src, dst, what = sys.argv[1:4]
    data = bytearray(open(src, "rb").read())
    if what.startswith("flip:"):
        data[int(what[5:])] ^= 0x01  # damage only: no reseal
    elif what == "legacy":
        data[:] = data.replace(KEY, b"deepsea:bytes\0\0\0\0")  # as before the record existed
    else:
        if what == "no-backscatter":
            data[:] = data.replace(b"backscatter", b"backscattex")
        elif what == "bad-json":
            edit_json(data, lambda j: b"[" + j[1:])
        elif what == "negative-attenuation":
            def neg(j):
                m = re.search(rb'"attenuation":\[([^,\]]+)', j)
                return j[:m.start(1)] + same_length(m.group(1), b"-1") + j[m.end(1):]
            edit_json(data, neg)
        elif what == "zero-lamps":
            def none(j):
                m = re.search(rb'"lights":\[', j)
                end = brackets(j, m.end() - 1)
                return j[:m.end()] + b" " * (end - m.end()) + j[end:]
            edit_json(data, none)
        elif what != "reseal":
            sys.exit("unknown edit " + what)
        seal(data)
    open(dst, "wb").write(data)


main()
