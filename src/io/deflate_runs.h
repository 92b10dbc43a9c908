#pragma once
// A zlib stream (RFC 1950/1951) of literals and runs, private to deepsea_io: PNG's filtered rows
// coded block by block with their own Huffman codes, each run of one byte (four or more) as a
// match at distance 1, no other matches searched (zlib's Z_RLE strategy). On PNG rows filtered
// "up" a search for matches finds few: sensor noise leaves deflate almost nothing to match, and
// a smooth rendered frame's residuals are mostly small values coded well as literals, while
// flat areas are runs of zero (docs/runtime.md, "Image I/O", has the sizes and times).
// Written here, not taken from a library: zlib's own Z_RLE makes the same kind of stream at
// about 6-8 times this code's CPU time, and igzip level 1 (matches searched) at about twice it
// (docs/runtime.md, "Image I/O").

#include <cstddef>
#include <cstdint>

namespace deepsea::io_detail {

/// Room `deflate_runs` needs for `size` bytes: each block is the smaller of its Huffman coding
/// and a stored block, plus an 8-byte margin the bit writer stores whole words into.
std::size_t deflate_runs_bound(std::size_t size);

/// Writes the zlib stream of `in` (`size` bytes) to `out` (at least deflate_runs_bound(size)
/// bytes) and returns its size.
std::size_t deflate_runs(const std::uint8_t* in, std::size_t size, std::uint8_t* out);

}  // namespace deepsea::io_detail
