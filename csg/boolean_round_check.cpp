// The rounding repair's exact check (boolean_round.cpp mends what it finds): rounded triangles
// turned over in their source's projection, degenerate, or meeting another beyond what they share.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <numeric>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

namespace {

// The orientation of rounded triangle t in the projection along its source's axis (exact).
int projected_sign(const Mesh& m, const Rounding& rd, std::size_t t) {
  return projected_orientation(m, t, rd.soup->axis[rd.src[t]]);
}

}  // namespace

Mesh sub_mesh(const Mesh& m, const std::vector<u32>& ids) {
  Mesh out;
  std::vector<u32> index(m.positions.size(), kNone);
  for (u32 t : ids) {
    std::array<u32, 3> T;
    for (int k = 0; k < 3; ++k) {
      u32& i = index[m.triangles[t][k]];
      if (i == kNone) {
        i = static_cast<u32>(out.positions.size());
        out.positions.push_back(m.positions[m.triangles[t][k]]);
      }
      T[k] = i;
    }
    out.triangles.push_back(T);
  }
  return out;
}


// Triangles to recheck (rd.recheck) that are degenerate, turned over in their source's
// projection, or meet another triangle beyond their shared vertices, decided exactly on the
// rounded doubles. Pairs of triangles neither of which is to be rechecked are not looked at: they
// were found apart by an earlier check and have not changed since.
std::vector<u32> rounding_defects(const Mesh& m, const Rounding& rd) {
  const std::size_t nt = m.triangles.size();
  std::vector<u32> check;
  for (std::size_t t = 0; t < nt; ++t)
    if (rd.recheck[t]) check.push_back(static_cast<u32>(t));
  if (check.empty()) return {};
  // The triangles looked at: all of them, or (fewer than a quarter to recheck: after a repair
  // round, or the first check where rounding moved only the cuts' points) those whose boxes meet a
  // rechecked one's, found through a tree over the rechecked ones alone. (Two 65k spheres' union
  // rechecks 4% of its 88,694 triangles: the soup and tree of all of them took 11 of 16 ms.)
  Mesh part_mesh;
  const Mesh* mesh = &m;
  std::vector<u32> part;  // soup triangle -> mesh triangle, when a part is taken
  if (check.size() * 4 < nt) {
    const Mesh few = sub_mesh(m, check);
    std::vector<const Mesh*> one{&few};
    const Soup fs = make_soup(one, rd.soup->interrupt);
    std::vector<u32> ids(check.size());
    std::iota(ids.begin(), ids.end(), 0u);
    const Bvh near(fs, std::move(ids), 3);
    // Most triangles lie off the tree's box (off_box codes; two 1M spheres: 1,373,088 triangles,
    // of which 21,678 are taken).
    const Bvh::Node& root = near.nodes[0];
    std::vector<std::uint8_t> code(m.positions.size());
    const Vec3 at(near.origin[0], near.origin[1], near.origin[2]);  // (the tree's boxes are offsets from it)
    parallel_for(0, m.positions.size(), [&](std::size_t v) { code[v] = off_box(Vec3(m.positions[v] - at), root.lo, root.hi); });
    std::vector<char> take(nt, 0);
    parallel_for(0, nt, [&](std::size_t u) {
      const auto& T = m.triangles[u];
      if (rd.recheck[u]) take[u] = 1;
      else if (!(code[T[0]] & code[T[1]] & code[T[2]])) {
        double lo[3], hi[3];
        mesh_triangle_box(m, u, lo, hi);
        take[u] = near.meets(lo, hi);
      }
    });
    for (std::size_t t = 0; t < nt; ++t)
      if (take[t]) part.push_back(static_cast<u32>(t));
    part_mesh = sub_mesh(m, part);
    mesh = &part_mesh;
  }
  auto orig = [&](u32 i) { return part.empty() ? i : part[i]; };
  std::vector<const Mesh*> one{mesh};
  Soup s = make_soup(one, rd.soup->interrupt);
  const std::size_t n = s.tris.size();
  std::vector<char> active(n);
  for (std::size_t i = 0; i < n; ++i) active[i] = rd.recheck[orig(static_cast<u32>(i))];
  // Triangles turned over (or degenerate): bad, and their clashes not looked for. Decided before
  // the pairs, so that which pairs are tested does not depend on the order threads visit them in.
  std::vector<char> turned(n, 0);
  std::vector<std::atomic<char>> bad(n);
  parallel_for(0, n, [&](std::size_t i) {
    const u32 t = orig(static_cast<u32>(i));
    if (active[i] && (s.axis[i] < 0 || projected_sign(m, rd, t) != rd.sign[t])) turned[i] = bad[i] = 1;
  });
  // The tree, and the stars certified embedded (pairs around such a vertex cannot cross), made
  // side by side: each is mostly serial at the classic figure's size (0.5 ms apiece on its
  // cube n sphere, whose check this made 0.3 ms shorter at two threads).
  Bvh bvh;
  std::vector<std::uint8_t> cert;
  parallel_invoke(
      [&] {
        std::vector<u32> all(n);
        std::iota(all.begin(), all.end(), 0u);
        bvh = Bvh(s, std::move(all), 3);
      },
      [&] { cert = star_certificates(s, nullptr, &active); });
  // The pieces of one face of one operand (a cone's side cut near its apex: its long thin
  // triangles' boxes met pairwise, 20 million pairs) certified embedded by their projection, on
  // the rounded doubles: no pair within one can meet beyond what it shares. Grouped by (operand,
  // face id) of their sources.
  std::vector<u32> group;
  {
    std::vector<std::uint64_t> key(n);
    for (std::size_t i = 0; i < n; ++i) {
      const u32 src = rd.src[orig(static_cast<u32>(i))];
      const std::int32_t f = rd.soup->face_id[src];
      key[i] = f < 0 ? ~std::uint64_t(0)
                     : static_cast<std::uint64_t>(static_cast<std::uint32_t>(rd.soup->operand[src])) << 32 | static_cast<std::uint32_t>(f);
    }
    std::vector<std::uint64_t> keys = key;
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (std::size_t i = 0; i < n; ++i)
      s.face_id[i] = key[i] == ~std::uint64_t(0) ? -1
                     : static_cast<std::int32_t>(std::lower_bound(keys.begin(), keys.end(), key[i]) - keys.begin());
    group = embedded_groups(s, nullptr);
  }
  // Shells touching along an edge that rounding turned into each other there (no triangle
  // crosses another: the pairs below cannot see it).
  for (u32 t : folded_edges(s, cert, &active)) bad[t] = 1;
  bvh.each_pair(
      &active, &s,
      [&](u32 t, u32 u) {
        const bool want_t = active[t] && !turned[t];
        const bool want_u = active[u] && !turned[u];
        // (apart first: a few dot products settle most pairs, the exact test's orientations of
        // six points the rest; the long thin pieces of a cut cone's side have boxes that meet
        // hundreds of their neighbours', and the exact tests of those pairs took 0.6 s.)
        if ((want_t || want_u) && !apart(s, t, u, false) && triangles_clash(s, t, u)) {
          // Both: the one not rechecked may be the one whose vertex can move (a rounded cut
          // point tilting it into an input triangle that nothing moved).
          bad[t] = 1;
          bad[u] = 1;
        }
      },
      &cert, group.empty() ? nullptr : &group);
  std::vector<u32> out;
  for (std::size_t i = 0; i < n; ++i)
    if (bad[i]) out.push_back(orig(static_cast<u32>(i)));
  return out;
}

}  // namespace wedge::boolean_detail
