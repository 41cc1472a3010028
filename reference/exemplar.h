// exemplar.h — flat periodic fabric exemplars for the precomputed light
// transport of Khungurn et al. 2017 (004 §2, §4.1; notes-appearance §0.3 A1):
// a block of procedural fibers (000 §3, the project's generator, from a yarn
// preset of data/yarn-presets.tsv) cut into straight segments (004 §2: "3D
// polyline of straight segments", midpoint μ_k), and its N × N tiling.
//
// Plain weave (A1): one period P × P holds 2 warp yarns along x at
// y = P/4, 3P/4 and 2 weft yarns along y at x = P/4, 3P/4 with sinusoidal
// centre lines (period P, amplitude h) that alternate over/under:
//   warp j: z = (−1)^j h sin(2πx/P),   weft i: z = −(−1)^i h sin(2πy/P),
// so at every crossing (x_i, y_j) the two centres are 2h apart. P = 4 ρ and
// h = ρ, ρ the yarn's reach (ply centre radius + ply half-axis, [F]): yarns
// side by side touch, crossing yarns touch. The fabric frame is z up.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace ft {

struct ExemplarSettings {
  std::string yarn = "polyester1";      // data/yarn-presets.tsv row
  std::vector<std::string> sets;        // --set name=value overrides of the preset
  int fibersPerPly = 6;                 // fiber_num override (0: the preset's); CI keeps it small
  int spansPerYarn = 8;                 // Catmull-Rom spans per yarn per period
  int subdivisions = 2;                 // straight segments per fiber per span
  float fiberRadius = 0.0008f;          // notes A1 (Fleece: 0.00087 cm)
  uint32_t seed = 1;                    // the fiber table's seed
};

struct ExemplarSegment {
  glm::vec3 a{0.0f}, b{0.0f};  // endpoints
  float radius = 0.0f;
  uint32_t fiber = 0;          // dense fiber id within the block (or the tiling)
  glm::vec3 mid() const { return 0.5f * (a + b); }
};

struct Exemplar {
  std::vector<ExemplarSegment> segments;  // the block's segments in the generator's order: span by span, ply, fiber, along the fiber
  uint32_t fibers = 0;                    // distinct fibers (ids 0 .. fibers − 1)
  float period = 0.0f;                    // P: the block is [0, P)² in x, y (fibers may reach a little beyond)
  float amplitude = 0.0f;                 // h
  float reach = 0.0f;                     // ρ
  std::string label;                      // "plain-weave polyester1 (6 fibers/ply, …)"
};

// The plain-weave block. Throws InputError naming the option for bad settings
// (unknown yarn, non-positive counts, --set errors).
Exemplar makePlainWeaveExemplar(const ExemplarSettings& settings);

// Throws InputError naming segment `index` unless its endpoints and radius
// are finite, the radius > 0 and (distinct) the endpoints differ.
void checkExemplarSegment(const ExemplarSegment& segment, size_t index, bool distinct = true);

// N × N copies of the block translated by (i − ⌊N/2⌋, j − ⌊N/2⌋)·P, copy
// c = j·N + i holding segments c·S .. c·S + S − 1 and fibers c·F .. c·F + F − 1
// (a fiber that crosses a block edge is a different fiber in the next copy:
// the generator's fibers do not continue across the seam [F]). The block at
// the centre, c = ⌊N/2⌋·N + ⌊N/2⌋, is untranslated (004 §4.1: the copy
// nearest the centre of the flat fabric).
std::vector<ExemplarSegment> tileExemplar(const Exemplar& block, int tiles);
inline size_t centreCopy(int tiles) { return size_t(tiles / 2) * size_t(tiles) + size_t(tiles / 2); }

}  // namespace ft
