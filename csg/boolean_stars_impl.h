// The operand checks that need no pairwise test (boolean_stars.cpp): corner lists, star
// certificates (a vertex's star one-to-one along a direction), the radial check (a whole operand
// one-to-one on the sphere of directions around a point) and pinched vertices. Included at the
// end of boolean_impl.h, whose Soup it uses.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "csg/boolean_impl.h"

namespace wedge::boolean_detail {

// Per vertex v, its corners [off[v], off[v + 1]) in ascending triangle order: next[k] = (the
// corner's next vertex << 32 | triangle), prev[k] = (its previous vertex << 32 | triangle). Made
// once for the operand check and the star certificates.
struct CornerLists {
  std::vector<u32> off;
  std::vector<std::uint64_t, NoInit<std::uint64_t>> next, prev;
};
// The corners of the triangles of the operands `listed` marks (all where null), at the vertices
// `wanted` marks (all where null).
CornerLists corner_lists(const Soup& soup, const std::vector<char>* listed, const std::vector<char>* wanted = nullptr);

// Per triangle, a 3-bit mask: bit c set when the star of the triangle's corner c (its triangles
// around that vertex in the triangle's operand) is certified to be embedded: seen along one
// direction every star triangle has the same orientation and the rim winds once (exact). Two
// triangles of a certified star meet only in what they share. Operands marked in `trusted` get
// no certificates (they are not checked). With `active` (per triangle), only the vertices of
// active triangles are looked at.
std::vector<std::uint8_t> star_certificates(const Soup& soup, const std::vector<char>* trusted = nullptr,
                                            const std::vector<char>* active = nullptr);
// The same from corner lists already made (whose triangles are the ones certified).
std::vector<std::uint8_t> star_certificates(const Soup& soup, const CornerLists& corners);
// Per operand: whether it is certainly free of self-intersections because it is one shell seen
// one-to-one from the mean of its vertices (see boolean_stars.cpp); operands marked in `skip`
// are not looked at (false). `corners`: the corner lists of the operands not skipped. With
// `facing`, per operand: 1 where every triangle faces away from that point (seen from it
// counter-clockwise: the volume is a sum of positive tetrahedra, so positive, exactly), -1 where
// every one faces it (negative), 0 where not known (the operand closed and consistently oriented).
std::vector<char> radially_embedded(const Soup& soup, const std::vector<char>* skip, const CornerLists& corners,
                                    std::vector<std::int8_t>* facing = nullptr);
// The vertices where the triangles of an operand marked in `look` make more than one fan (the
// corner lists hold those operands' corners), ascending.
std::vector<u32> pinched_vertices(const Soup& soup, const CornerLists& corners, const std::vector<char>& look);
// The triangles about edges of three or more of one operand (shells that touch along an edge,
// their positions welded) that are not, in their exact order about the edge, alternately from and to its smaller
// end, or of which two lie in one half-plane. Two shells sharing such an edge then overlap in the
// wedge between two of their triangles, though no two triangles cross (a wedge 1e-8 rad thin,
// turned over where rounding moved its edge's end: the fuzzer's grid_rot seed 6103). Only edges of
// triangles `active` marks (all where null) neither of whose ends has a certified star in `cert`
// (a certified star is one embedded fan, whose edges have two triangles each). Ascending.
std::vector<u32> folded_edges(const Soup& soup, const std::vector<std::uint8_t>& cert, const std::vector<char>* active);
// Whether triangle T (its star_certificates() mask `cert`) and triangle U share a vertex whose
// star is certified at T's corner (so they cannot clash).
inline bool shares_certified(const std::array<u32, 3>& T, std::uint8_t cert, const std::array<u32, 3>& U) {
  for (int c = 0; c < 3; ++c)
    if ((cert >> c & 1) && (T[c] == U[0] || T[c] == U[1] || T[c] == U[2])) return true;
  return false;
}

}  // namespace wedge::boolean_detail
