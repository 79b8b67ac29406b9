// Star certificates and radial embedding: the operand checks that need no pairwise test (a
// vertex's star seen one-to-one along a direction; a whole operand one-to-one on the sphere of
// directions around a point), for the broad phase and the rounding check.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <tuple>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

// Star certificates for the self-intersection check. The star of vertex v in one operand (its
// triangles around v) is *certified* when, seen along some direction d, every star triangle has
// the same non-zero orientation and the rim winds once around v: then the projection along d is
// one-to-one on the star, so two star triangles meet only in what they share (v, or an edge from
// v) and need no pairwise test. d is W - V for a double W near V + the star's mean normal, and
// each orientation is orient3d(V, a, b, W), exact: the certificate is exact whatever W is.
// Closed meshes' stars are nearly all certified (a sphere's, a cylinder's cap fans and rims, a
// box's corners); a star that is not is tested pairwise as before. Returns per triangle a 3-bit
// mask: bit c set when the star at corner c is certified.
CornerLists corner_lists(const Soup& soup, const std::vector<char>* listed, const std::vector<char>* wanted) {
  const std::size_t nt = soup.tris.size(), nv = soup.verts.size();
  CornerLists cl;
  auto take = [&](std::size_t t) { return !listed || (*listed)[soup.operand[t]]; };
  // A counting sort of the corners by vertex, over a few chunks of the triangles at once: chunk
  // c's corners of vertex v go after chunks 0..c-1's, so each vertex's corners are in triangle
  // order, as one pass would put them.
  const std::size_t chunks =
      nt < (std::size_t(1) << 16) ? 1 : std::min<std::size_t>(8, thread_count());
  const std::size_t per = (nt + chunks - 1) / chunks;
  std::vector<std::vector<u32>> at(chunks);
  parallel_for(0, chunks, [&](std::size_t c) {
    at[c].assign(nv, 0);
    for (std::size_t t = c * per; t < std::min(nt, (c + 1) * per); ++t)
      if (take(t))
        for (u32 v : soup.tris[t])
          if (!wanted || (*wanted)[v]) ++at[c][v];
  });
  soup.poll();
  cl.off.resize(nv + 1);
  chunk_offsets(at, nv, cl.off);
  soup.poll();
  cl.next.resize(cl.off[nv]);
  cl.prev.resize(cl.off[nv]);
  parallel_for(0, chunks, [&](std::size_t c) {
    for (std::size_t t = c * per; t < std::min(nt, (c + 1) * per); ++t)
      if (take(t))
        for (int k = 0; k < 3; ++k) {
          const u32 v = soup.tris[t][k];
          if (wanted && !(*wanted)[v]) continue;
          const u32 i = at[c][v]++;
          cl.next[i] = static_cast<std::uint64_t>(soup.tris[t][(k + 1) % 3]) << 32 | static_cast<u32>(t);
          cl.prev[i] = static_cast<std::uint64_t>(soup.tris[t][(k + 2) % 3]) << 32 | static_cast<u32>(t);
        }
  });
  return cl;
}

std::vector<std::uint8_t> star_certificates(const Soup& soup, const std::vector<char>* trusted,
                                            const std::vector<char>* active) {
  std::vector<char> listed(soup.operands, 1), wanted;
  if (trusted)
    for (int o = 0; o < soup.operands; ++o) listed[o] = !(*trusted)[o];
  if (active) {
    wanted.assign(soup.verts.size(), 0);
    for (std::size_t t = 0; t < soup.tris.size(); ++t)
      if ((*active)[t])
        for (u32 v : soup.tris[t]) wanted[v] = 1;
  }
  return star_certificates(soup, corner_lists(soup, &listed, active ? &wanted : nullptr));
}

std::vector<std::uint8_t> star_certificates(const Soup& soup, const CornerLists& cl) {
  const std::size_t nt = soup.tris.size(), nv = soup.verts.size();
  std::vector<std::uint8_t> mask(nt, 0);
  const std::vector<u32>& off = cl.off;
  soup.poll();
  // Where most corners are listed: per vertex whose corners are of one operand, that operand
  // where its star is certified (-1 otherwise), and the triangles' bits set from it afterwards,
  // without an atomic per corner (a quarter of the radial check of two 1M-triangle spheres).
  const bool by_vertex = cl.next.size() >= nt;
  std::vector<std::int32_t> whole(by_vertex ? nv : 0, -1);
  parallel_for(0, (nv + 1023) / 1024, [&](std::size_t block) {
    soup.poll();
    struct Spoke {
      u32 a, b, rec;  // triangle (v, a, b) counter-clockwise, its record
    };
    std::vector<Spoke> star;
    std::vector<u32> rim, rim_rec;
    for (std::size_t v = block * 1024; v < std::min(nv, (block + 1) * 1024); ++v) {
      for (u32 r0 = off[v]; r0 < off[v + 1];) {
        u32 r1 = r0;
        const std::int32_t op = soup.operand[static_cast<u32>(cl.next[r0])];
        while (r1 < off[v + 1] && soup.operand[static_cast<u32>(cl.next[r1])] == op) ++r1;  // one operand's star of v
        star.clear();
        for (u32 r = r0; r < r1; ++r) star.push_back({static_cast<u32>(cl.next[r] >> 32), static_cast<u32>(cl.prev[r] >> 32), r});
        const u32 first = r0;
        r0 = r1;
        if (star.size() < 3) continue;
        // The rim as one cycle a1 -> a2 -> ... -> a1 (each spoke's b is the next spoke's a); a
        // star that is not one cycle (a vertex where two cones touch) gets no certificate.
        std::sort(star.begin(), star.end(), [](const Spoke& x, const Spoke& y) { return x.a < y.a; });
        bool ok = true;
        for (std::size_t i = 1; i < star.size() && ok; ++i) ok = star[i].a != star[i - 1].a;
        if (!ok) continue;
        auto next = [&](u32 a) -> const Spoke* {
          auto it = std::lower_bound(star.begin(), star.end(), a, [](const Spoke& x, u32 y) { return x.a < y; });
          return it != star.end() && it->a == a ? &*it : nullptr;
        };
        rim.clear();
        rim_rec.clear();
        const Spoke* sp = &star[0];
        for (std::size_t n = 0; n < star.size() && sp; ++n) {
          rim.push_back(sp->a);
          rim_rec.push_back(sp->rec);
          sp = next(sp->b);
        }
        if (!sp || sp != &star[0] || rim.size() != star.size()) continue;  // not one cycle
        // Seen along d = W - V, W a double near V + (the star's mean normal): any W would be
        // exact, this one makes most stars pass.
        const Vec3& V = soup.verts[v];
        Vec3 W;
        {
          Vec3 nrm = Vec3::Zero();
          for (std::size_t m = 0; m < rim.size(); ++m) {
            const Vec3 &P = soup.verts[rim[m]], &Q = soup.verts[rim[(m + 1) % rim.size()]];
            nrm += (P - V).cross(Q - V);
          }
          const double len = (soup.verts[rim[0]] - V).norm(), nn = nrm.norm();
          if (!(nn > 0) || !(len > 0)) continue;
          W = V + nrm * (len / nn);
        }
        if (W == V || !W.allFinite()) continue;
        auto orient = [&](const Vec3& a, const Vec3& b) { return orient3d_fast(V, a, b, W); };
        // Spoke m's triangle (v, rim[m], rim[m + 1]) seen from W.
        auto spoke = [&](std::size_t m) {
          return orient(soup.verts[rim[m]], soup.verts[rim[(m + 1) % rim.size()]]);
        };
        const std::size_t n = rim.size();
        const int s = spoke(0);
        if (s == 0) continue;
        for (std::size_t m = 1; m < n && ok; ++m) ok = spoke(m) == s;
        if (!ok) continue;
        // Winding number of the rim about v: the last step ends on the direction of a1 (one turn);
        // any earlier step that reaches or passes it adds a turn (a step ending on the line of a1
        // is not sorted out here: no certificate).
        // (A step's start, orient(P, A1), is the last step's end orient(A1, P) negated: the
        // predicate is exact, and swapping two points negates it. One orientation per step.)
        const Vec3& A1 = soup.verts[rim[0]];
        int start = -orient(A1, soup.verts[rim[1]]);  // a star has three spokes or more
        for (std::size_t m = 1; m + 1 < n && ok; ++m) {
          const int end = orient(A1, soup.verts[rim[m + 1]]);
          // A step that starts on or past the direction of a1 is passed over.
          if (s * start > 0 && s * end >= 0) ok = false;
          start = -end;
        }
        if (!ok) continue;
        if (by_vertex && first == off[v] && r1 == off[v + 1]) {  // the vertex's only star
          whole[v] = op;
          continue;
        }
        for (u32 r = first; r < r1; ++r) {
          const u32 t = static_cast<u32>(cl.next[r]);
          const u32 c = soup.tris[t][0] == v ? 0 : (soup.tris[t][1] == v ? 1 : 2);
          // (A triangle's three corners are certified from three vertices, in any blocks: with a
          // plain |= a bit set at the same time by another block could be lost.)
          std::atomic_ref<std::uint8_t>(mask[t]).fetch_or(static_cast<std::uint8_t>(1u << c), std::memory_order_relaxed);
        }
      }
    }
  });
  if (by_vertex)
    parallel_for(0, (nt + 4095) / 4096, [&](std::size_t block) {
      for (std::size_t t = block * 4096; t < std::min(nt, (block + 1) * 4096); ++t) {
        const auto& T = soup.tris[t];
        const std::int32_t op = soup.operand[t];
        mask[t] |= static_cast<std::uint8_t>((whole[T[0]] == op) | (whole[T[1]] == op) << 1 | (whole[T[2]] == op) << 2);
      }
    });
  return mask;
}

// An operand all of whose triangles, seen from one point c, have one orientation maps onto the
// sphere of directions around c by a branched covering (each triangle onto a spherical triangle,
// the two triangles at an edge on either side of its arc; the closed, oriented operand check
// came first): Riemann-Hurwitz gives chi' = 2d - B, where d is the covering's degree, B >= 0 its
// branching at vertices (a star that winds k times adds k - 1) and chi' = V - E + F + p the
// Euler characteristic once each of p pinched vertices is split. With V - E + F = 2 and d = 1,
// p = B = 0: the map is one-to-one, and no two triangles meet beyond what they share. d is the
// number of triangles that a ray from c crosses (each crossing counts once, every triangle facing
// the same way), exact for a ray that meets no edge or vertex: it goes through the centroid of
// one of the operand's triangles, and a few others are tried where it meets an edge or vertex.
// Convex and star-shaped operands (boxes, cylinders, spheres: nearly every primitive) pass with
// c the mean of their vertices, in linear time and without looking at pairs. Where no ray is
// found, the operand's stars are certified one by one from c instead (star_certificates).
namespace {

struct Ray {
  Vec3 to;      // a double point: the ray goes from the operand's c through it
  Vec3 n1, n2;  // two directions across the ray: the planes through c across them nearly hold it
  double tol;   // a vertex further than this from such a plane is surely on its side
};

// The ray through the centroid of triangle t of the operand centred at c; false where that is c.
bool ray_through(const Soup& soup, u32 t, const Vec3& c, double reach, Ray& ray) {
  const auto& T = soup.tris[t];
  ray.to = (soup.verts[T[0]] + soup.verts[T[1]] + soup.verts[T[2]]) / 3.0;
  const Vec3 d = ray.to - c;
  const double len = d.norm();
  if (!(len > 0) || !std::isfinite(len)) return false;
  const Vec3 u = d / len;
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(u[a]) < std::abs(u[k])) k = a;
  ray.n1 = u.cross(Vec3::Unit(k)).normalized();
  ray.n2 = u.cross(ray.n1).normalized();
  // Within `reach` of c (every vertex is), the ray is within a few ulps of reach from both planes
  // (d has rounding in it, the normals are orthogonal to it within rounding), and a dot product
  // of a vertex with a normal errs by a few ulps of reach: 1e-12 is thousands of times that.
  ray.tol = 1e-12 * reach;
  return std::isfinite(ray.tol) && ray.n1.allFinite() && ray.n2.allFinite();
}

}  // namespace

std::vector<char> radially_embedded(const Soup& soup, const std::vector<char>* skip, const CornerLists& corners,
                                    std::vector<std::int8_t>* facing) {
  const int nops = soup.operands;
  const std::size_t nt = soup.tris.size(), nv = soup.verts.size();
  const std::vector<u32> first = operand_starts(soup);  // an operand's triangles are one run
  std::vector<std::size_t> faces(nops, 0);
  for (int op = 0; op < nops; ++op) faces[op] = first[op + 1] - first[op];
  // Each operand's vertices (a vertex's corners of one operand are one run of its list): their
  // number, mean and box, per block of vertices in parallel, the blocks summed in order.
  const std::size_t blocks = (nv + 65535) / 65536;
  struct Part {
    Vec3 sum = Vec3::Zero(), lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    std::size_t count = 0;
  };
  std::vector<std::vector<Part>> parts(blocks);
  parallel_for(0, blocks, [&](std::size_t b) {
    parts[b].assign(nops, Part{});
    auto add = [&](std::int32_t op, const Vec3& p) {
      Part& part = parts[b][op];
      part.sum += p;
      part.lo = part.lo.cwiseMin(p);
      part.hi = part.hi.cwiseMax(p);
      ++part.count;
    };
    for (std::size_t v = b * 65536; v < std::min(nv, (b + 1) * 65536); ++v) {
      const u32 k0 = corners.off[v], k1 = corners.off[v + 1];
      if (k0 == k1) continue;
      // A vertex whose positions are all of one operand has only that operand's corners (nearly
      // every vertex); else the corners, in triangle order and so in operand order, say whose.
      if (const std::int32_t op0 = v < soup.vertex_operand.size() ? soup.vertex_operand[v] : -1; op0 >= 0) {
        add(op0, soup.verts[v]);
        continue;
      }
      std::int32_t prev = -1;
      for (u32 k = k0; k < k1; ++k) {
        const std::int32_t op = soup.operand[static_cast<u32>(corners.next[k])];
        if (op == prev) continue;
        prev = op;
        add(op, soup.verts[v]);
      }
    }
  });
  std::vector<Vec3> centers(nops, Vec3::Zero()), lo(nops, Vec3::Constant(INFINITY)), hi(nops, Vec3::Constant(-INFINITY));
  std::vector<std::size_t> verts(nops, 0);
  for (std::size_t b = 0; b < blocks; ++b)
    for (int op = 0; op < nops; ++op) {
      const Part& p = parts[b][op];
      centers[op] += p.sum;
      lo[op] = lo[op].cwiseMin(p.lo);
      hi[op] = hi[op].cwiseMax(p.hi);
      verts[op] += p.count;
    }
  std::vector<char> pass(nops, 0);
  std::vector<char> todo(nops, 0);
  for (int op = 0; op < nops; ++op) {
    centers[op] /= static_cast<double>(std::max<std::size_t>(verts[op], 1));
    // V - E + F with E = 3F / 2 (closed: every edge in two triangles).
    const auto chi = static_cast<std::int64_t>(verts[op]) - static_cast<std::int64_t>(faces[op] / 2);
    todo[op] = (!skip || !(*skip)[op]) && faces[op] > 0 && faces[op] % 2 == 0 && chi == 2 && centers[op].allFinite();
  }
  // Per operand: how far its vertices reach from c at most (from its box; for the rays).
  std::vector<double> reach(nops, 0);
  for (int op = 0; op < nops; ++op)
    if (todo[op]) reach[op] = (hi[op] - centers[op]).cwiseAbs().cwiseMax((lo[op] - centers[op]).cwiseAbs()).norm();
  std::vector<Ray> ray(nops);
  for (int op = 0; op < nops; ++op)
    if (todo[op]) todo[op] = ray_through(soup, first[op], centers[op], 2 * reach[op], ray[op]);
  // One pass over the triangles: each one's orientation seen from its operand's c (the signs
  // met, per operand), and those the ray may cross (near both planes along it).
  constexpr std::size_t kBlock = 65536;
  const std::size_t tblocks = (nt + kBlock - 1) / kBlock;
  std::vector<std::vector<std::uint8_t>> signs(tblocks);
  std::vector<std::vector<u32>> near(tblocks);
  parallel_for(0, tblocks, [&](std::size_t b) {
    soup.poll();
    signs[b].assign(nops, 0);
    for (std::size_t t = b * kBlock; t < std::min(nt, (b + 1) * kBlock); ++t) {
      const std::int32_t op = soup.operand[t];
      if (!todo[op]) continue;
      const auto& T = soup.tris[t];
      const Vec3 &A = soup.verts[T[0]], &B = soup.verts[T[1]], &C = soup.verts[T[2]], &c = centers[op];
      const int s = orient3d_fast(A, B, C, c);
      signs[b][op] |= static_cast<std::uint8_t>(s > 0 ? 1 : s < 0 ? 2 : 4);
      const Ray& r = ray[op];
      const double a1 = (A - c).dot(r.n1), b1 = (B - c).dot(r.n1), c1 = (C - c).dot(r.n1);
      const double a2 = (A - c).dot(r.n2), b2 = (B - c).dot(r.n2), c2 = (C - c).dot(r.n2);
      auto apart = [&](double x, double y, double z) {
        return (x > r.tol && y > r.tol && z > r.tol) || (x < -r.tol && y < -r.tol && z < -r.tol);
      };
      if (!apart(a1, b1, c1) && !apart(a2, b2, c2)) near[b].push_back(static_cast<u32>(t));
    }
  });
  std::vector<std::uint8_t> seen(nops, 0);
  for (const auto& sb : signs)
    for (int op = 0; op < nops; ++op) seen[op] |= sb[op];
  std::vector<u32> candidates;
  for (const auto& nb : near) candidates.insert(candidates.end(), nb.begin(), nb.end());
  // The crossings of each operand's ray, exact: a triangle (a, b, d) facing c is crossed where
  // the ray's point is on d's side of the plane (c, a, b), and likewise for its other two edges.
  std::vector<std::size_t> crossed(nops, 0);
  std::vector<char> unclear(nops, 0);
  auto count = [&](u32 t) {
    const std::int32_t op = soup.operand[t];
    const auto& T = soup.tris[t];
    const Vec3 &c = centers[op], &to = ray[op].to;
    const int ref = orient3d_fast(c, soup.verts[T[0]], soup.verts[T[1]], soup.verts[T[2]]);
    int same = 0, zero = 0;
    for (int e = 0; e < 3; ++e) {
      const int s = orient3d_fast(c, soup.verts[T[e]], soup.verts[T[(e + 1) % 3]], to);
      same += s == ref;
      zero += s == 0;
    }
    if (same == 3) ++crossed[op];
    else if (same + zero == 3) unclear[op] = 1;  // through an edge or a vertex
  };
  for (int op = 0; op < nops; ++op)
    if (todo[op] && (seen[op] == 1 || seen[op] == 2)) pass[op] = 1;
  // (orient3d(a, b, d, c) < 0: c behind the triangle, det[a - c, b - c, d - c] > 0.)
  if (facing)
    for (int op = 0; op < nops; ++op) (*facing)[op] = !todo[op] ? 0 : seen[op] == 2 ? 1 : seen[op] == 1 ? -1 : 0;
  for (u32 t : candidates)
    if (pass[soup.operand[t]]) count(t);
  // A ray through an edge or a vertex: others, through other triangles' centroids, looked for
  // among all the operand's triangles (rare: a few tries; without a clear ray the operand is not
  // passed, and the broad phase checks its pairs).
  for (int op = 0; op < nops; ++op) {
    for (std::size_t k = 1; k <= 3 && pass[op] && unclear[op]; ++k) {
      const u32 t0 = static_cast<u32>(first[op] + k * faces[op] / 4);
      if (!ray_through(soup, t0, centers[op], 2 * reach[op], ray[op])) continue;
      crossed[op] = 0;
      unclear[op] = 0;
      for (u32 t = first[op]; t < first[op + 1]; ++t) count(t);
    }
  }
  for (int op = 0; op < nops; ++op) pass[op] = pass[op] && !unclear[op] && crossed[op] == 1;
  return pass;
}

std::vector<u32> pinched_vertices(const Soup& soup, const CornerLists& corners, const std::vector<char>& look) {
  const std::size_t nv = soup.verts.size();
  std::vector<std::vector<u32>> found((nv + 65535) / 65536);
  parallel_for(0, found.size(), [&](std::size_t block) {
    soup.poll();
    std::vector<std::pair<u32, u32>> spokes;  // (a, b): triangle (v, a, b)
    for (std::size_t v = block * 65536; v < std::min(nv, (block + 1) * 65536); ++v)
      for (u32 r0 = corners.off[v]; r0 < corners.off[v + 1];) {
        const std::int32_t op = soup.operand[static_cast<u32>(corners.next[r0])];
        u32 r1 = r0;
        spokes.clear();
        for (; r1 < corners.off[v + 1] && soup.operand[static_cast<u32>(corners.next[r1])] == op; ++r1)
          spokes.push_back({static_cast<u32>(corners.next[r1] >> 32), static_cast<u32>(corners.prev[r1] >> 32)});
        r0 = r1;
        if (!look[op]) continue;
        // One fan: from any spoke, each next one the spoke whose a is this one's b, all of them
        // before the first comes back (closed and oriented: each a and each b once).
        std::sort(spokes.begin(), spokes.end());
        std::size_t steps = 0;
        u32 at = spokes[0].first;
        do {
          auto it = std::lower_bound(spokes.begin(), spokes.end(), std::pair<u32, u32>{at, 0});
          if (it == spokes.end() || it->first != at) break;
          at = it->second;
          ++steps;
        } while (at != spokes[0].first && steps <= spokes.size());
        if (steps != spokes.size() || at != spokes[0].first) {
          found[block].push_back(static_cast<u32>(v));
          break;
        }
      }
  });
  std::vector<u32> out;
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
  return out;
}

std::vector<u32> folded_edges(const Soup& soup, const std::vector<std::uint8_t>& cert, const std::vector<char>* active) {
  const std::size_t nt = soup.tris.size();
  auto key = [](u32 a, u32 b) { return static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b); };
  // The edges to look at (few: most stars are certified), then every triangle on them.
  // (Triangles with a repeated vertex, gone in a repair round, are passed over.)
  auto gone = [&](std::size_t t) {
    const auto& T = soup.tris[t];
    return T[0] == T[1] || T[1] == T[2] || T[2] == T[0];
  };
  std::vector<std::uint64_t> look;
  for (std::size_t t = 0; t < nt; ++t) {
    if ((active && !(*active)[t]) || gone(t)) continue;
    for (int e = 0; e < 3; ++e)
      if (!(cert[t] >> e & 1) && !(cert[t] >> ((e + 1) % 3) & 1)) look.push_back(key(soup.tris[t][e], soup.tris[t][(e + 1) % 3]));
  }
  if (look.empty()) return {};
  std::sort(look.begin(), look.end());
  look.erase(std::unique(look.begin(), look.end()), look.end());
  // (Only edges whose ends are both ends of such edges are searched for.)
  std::vector<char> end(soup.verts.size(), 0);
  for (std::uint64_t k : look) end[k >> 32] = end[static_cast<u32>(k)] = 1;
  // (edge, operand, triangle): an operand's triangles about an edge are looked at by themselves
  // (where operands meet is the boolean's business).
  std::vector<std::tuple<std::uint64_t, std::int32_t, u32>> on;
  for (std::size_t t = 0; t < nt; ++t)
    for (int e = 0; e < 3 && !gone(t); ++e) {
      const u32 u = soup.tris[t][e], v = soup.tris[t][(e + 1) % 3];
      if (!end[u] || !end[v]) continue;
      const std::uint64_t k = key(u, v);
      if (std::binary_search(look.begin(), look.end(), k)) on.push_back({k, soup.operand[t], static_cast<u32>(t)});
    }
  std::sort(on.begin(), on.end());
  std::vector<u32> out;
  struct Sheet {
    u32 t;
    Vec3 c;     // the triangle's third corner
    bool from;  // the triangle runs a -> b
    int half;   // 0: less than a half-turn about a -> b from the first sheet (itself included)
  };
  std::vector<Sheet> sheets;
  for (std::size_t i = 0, j; i < on.size(); i = j) {
    for (j = i; j < on.size() && std::get<0>(on[j]) == std::get<0>(on[i]) && std::get<1>(on[j]) == std::get<1>(on[i]); ++j) {
    }
    if (j - i < 3) continue;
    const u32 a = static_cast<u32>(std::get<0>(on[i]) >> 32), b = static_cast<u32>(std::get<0>(on[i]));
    const Vec3 &A = soup.verts[a], &B = soup.verts[b];
    sheets.clear();
    for (std::size_t x = i; x < j; ++x) {
      const u32 t = std::get<2>(on[x]);
      const auto& T = soup.tris[t];
      int c = 0;
      while (T[c] == a || T[c] == b) ++c;
      sheets.push_back({t, soup.verts[T[c]], T[(c + 1) % 3] == a, 0});
    }
    // Angles about a -> b from the first sheet, positive where orient3d(A, B, C0, C) > 0: the
    // half-turn a sheet is in, then, within one, the order orient3d(A, B, Ci, Cj) > 0 gives.
    // (A sheet in the first one's plane: the same half-plane where the two corners lie on one
    // side of a b in a projection that keeps that plane's triangle non-degenerate.)
    const Vec3 n0 = (B - A).cross(sheets[0].c - A);
    int k = 0;
    for (int d = 1; d < 3; ++d)
      if (std::abs(n0[d]) > std::abs(n0[k])) k = d;
    const int pi = (k + 1) % 3, pj = (k + 2) % 3;
    auto side = [&](const Vec3& c) { return orient2d_fast(A[pi], A[pj], B[pi], B[pj], c[pi], c[pj]); };
    const int s0 = side(sheets[0].c);
    bool folded = s0 == 0;  // (a triangle of no area)
    for (Sheet& x : sheets) {
      const int o = orient3d_fast(A, B, sheets[0].c, x.c);
      x.half = o > 0 || (o == 0 && side(x.c) == s0) ? 0 : 1;
    }
    std::sort(sheets.begin(), sheets.end(), [&](const Sheet& x, const Sheet& y) {
      if (x.half != y.half) return x.half < y.half;
      return orient3d_fast(A, B, x.c, y.c) > 0;
    });
    const std::size_t n = sheets.size();
    for (std::size_t x = 0; x < n && !folded; ++x) {
      const Sheet &p = sheets[x], &q = sheets[(x + 1) % n];
      // Two in one half-plane (neither before the other), or two running the same way in a row.
      folded = p.from == q.from || (p.half == q.half && orient3d_fast(A, B, p.c, q.c) == 0);
    }
    if (folded)
      for (const Sheet& x : sheets) out.push_back(x.t);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace wedge::boolean_detail
