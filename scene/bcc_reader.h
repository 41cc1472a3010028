// bcc_reader.h — reader for BCC binary curve collections (Cem Yuksel's
// yarn-level models), format in the shared reference-data §1.
#pragma once
#include <cstddef>
#include <filesystem>
#include <span>
#include <string_view>

#include "scene/yarn_model.h"

namespace ft {

// Parses a whole BCC file image. `sourceName` is used in error messages.
// Every malformed input throws InputError("<sourceName>: byte <offset>: <what>");
// nothing else escapes (no crash, no partial model).
// Accepted: 0x44 byte counts, curve type C0, 3 dimensions, up dimension 1 (y up)
// or 2 (z up). Models are always y-up: z-up points are rotated on load,
// (x, y, z)_zup -> (x, z, -y) (a right-handed rotation about x).
// Rejected besides malformed structure: non-finite coordinates, open curves
// with < 2 points, closed ones with < 3, and coincident consecutive points.
// A closed curve whose last point repeats its first exactly (8 loops of the
// real glove.bcc) loses that copy: the wrap segment closes the loop anyway,
// and keeping it would leave a zero-length segment.
YarnModel parseBcc(std::span<const std::byte> bytes, std::string_view sourceName);

// Reads and parses a file; I/O failures are InputErrors too.
YarnModel readBcc(const std::filesystem::path& path);

// Writes a model as BCC (C0, 4-byte int/float, y-up); used by tests and by
// later tools that emit yarn curves. Catmull-Rom curves only.
void writeBcc(const YarnModel& model, const std::filesystem::path& path);

}  // namespace ft
