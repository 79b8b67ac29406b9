// Interning of the retriangulation's points: step 2 of arrange() (boolean_triangulate.cpp).
//
// Read serially, the step goes through the candidate pairs in order: a triangle's first cut seeds
// its vertices (by position), then each end point of each segment and each touching point gets
// its id (a new one at the first occurrence of its key: its position where its definition fixes
// all three coordinates, else its canonical definition) and joins the work of its triangles.
// Here the pairs are cut into a few runs of about equal work, one per thread, each read that way
// by itself: the first run adds its points to the table (their ids final), the others keep theirs
// apart. Then, run after run, each key a run made is looked up in the earlier runs: found, it
// takes the id it has there; else it is a new point (numbered on, in the run's order) or an input
// vertex seeded there. So every point gets the id the serial pass gives it, whatever the number
// of runs, and the runs' work per triangle is joined in pair order. A run seeds the triangles it
// cuts first; where an earlier run cut one already, that run has its vertices' positions, so the
// lookup finds them there.
#include <algorithm>
#include <bit>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

namespace {

Plane canonical(Plane p) {
  if (p.axis < 0) {
    // A cyclic rotation names the same oriented plane.
    while (p.a > p.b || p.a > p.c) {
      u32 t = p.a;
      p.a = p.b;
      p.b = p.c;
      p.c = t;
    }
  }
  return p;
}
// A plane's identity for interning: x_i = c (fixes_coordinate) is named by i and c, whichever
// triangle or wall gave it, so that a point cut from the same segment by two faces on one axis
// plane (a sponge's bars side by side, a plate's face and a boss's) is one point from the start
// rather than two that the equal-point pass pairs later; any other plane by its (canonical)
// vertices.
struct PlaneId {
  std::uint64_t hi, lo;
  bool operator==(const PlaneId& o) const { return hi == o.hi && lo == o.lo; }
  bool operator<(const PlaneId& o) const { return hi != o.hi ? hi < o.hi : lo < o.lo; }
};
PlaneId plane_id(const Soup& s, const Plane& P) {
  double c = 0;
  for (int i = 0; i < 3; ++i)
    if (fixes_coordinate(s, P, i, c)) return {static_cast<std::uint64_t>(5 + i) << 32, std::bit_cast<std::uint64_t>(c)};
  return {static_cast<std::uint64_t>(P.axis + 1) << 32 | P.a, static_cast<std::uint64_t>(P.b) << 32 | P.c};
}

PointDef canonical(const Soup& s, PointDef d) {
  if (d.kind == PointDef::Lpi) {
    if (d.p > d.q) std::swap(d.p, d.q);
    d.P[0] = canonical(d.P[0]);
  } else if (d.kind == PointDef::Tpi) {
    for (auto& p : d.P) p = canonical(p);
    const PlaneId id[3] = {plane_id(s, d.P[0]), plane_id(s, d.P[1]), plane_id(s, d.P[2])};
    int o[3] = {0, 1, 2};
    std::sort(o, o + 3, [&](int x, int y) { return id[x] < id[y]; });
    const Plane P[3] = {d.P[o[0]], d.P[o[1]], d.P[o[2]]};
    std::copy(P, P + 3, d.P);
  }
  return d;
}

// Of a canonical definition.
std::uint64_t def_hash(const Soup& s, const PointDef& d) {
  const int np = d.kind == PointDef::Tpi ? 3 : 1;
  std::uint64_t x = 0x9e3779b97f4a7c15ull;
  auto mix = [&](std::uint64_t v) { x = (x ^ v) * 0xff51afd7ed558ccdull; };
  mix(static_cast<std::uint64_t>(d.kind) << 32 | d.p);
  mix(d.q);
  for (int k = 0; k < np; ++k) {
    const PlaneId id = plane_id(s, d.P[k]);
    mix(id.hi);
    mix(id.lo);
  }
  return x ^ (x >> 29);
}
bool same_def(const Soup& s, const PointDef& e, const PointDef& d) {
  if (e.kind != d.kind || e.p != d.p || e.q != d.q) return false;
  const int np = d.kind == PointDef::Tpi ? 3 : 1;
  for (int k = 0; k < np; ++k)
    if (!(e.P[k] == d.P[k]) && !(plane_id(s, e.P[k]) == plane_id(s, d.P[k]))) return false;
  return true;
}

// A table slot: the hash's high 31 bits and a bit that says whether the key is a position, then
// an id (kEmpty where empty).
constexpr std::uint64_t kEmpty = ~0ull;
constexpr std::uint64_t kHigh = ~0ull << 32;
constexpr std::uint64_t kPlaceBit = 1ull << 32;
constexpr std::size_t kBlock = 1024;

// Calls f(i) for i in [0, n), in parallel blocks of kBlock, polling per block.
template <class F>
void blocks(const Soup& soup, std::size_t n, F&& f) {
  parallel_for(0, (n + kBlock - 1) / kBlock, [&](std::size_t b) {
    soup.poll();
    for (std::size_t i = b * kBlock, e = std::min(n, i + kBlock); i < e; ++i) f(i);
  });
}

std::uint64_t tag_of(std::uint64_t h, bool by_position) {
  return (h & kHigh & ~kPlaceBit) | (by_position ? kPlaceBit : 0);
}

// (Its blocks kept for the next run: kernel/memory.h.)
using Table = KeptVector<std::uint64_t>;

// The id of the key (hash h) for which same(id) holds, or kNone.
template <class Same>
u32 lookup(const Table& table, std::uint64_t h, bool by_position, Same&& same) {
  const std::uint64_t tag = tag_of(h, by_position);
  const std::size_t mask = table.size() - 1;
  for (std::size_t s = h & mask; table[s] != kEmpty; s = (s + 1) & mask)
    if ((table[s] & kHigh) == tag && same(static_cast<u32>(table[s]))) return static_cast<u32>(table[s]);
  return kNone;
}

// Puts (tag, id) in the table, whose keys are all different from it; rehash(slot value) gives the
// hash of a key already there, when the table grows.
template <class Rehash>
void put(Table& table, std::size_t& keys, std::uint64_t h, std::uint64_t tag, u32 id,
         Rehash&& rehash) {
  if (2 * ++keys > table.size()) {
    Table t(table.size() * 2, kEmpty);
    for (std::uint64_t v : table)
      if (v != kEmpty) {
        std::size_t x = rehash(v) & (t.size() - 1);
        while (t[x] != kEmpty) x = (x + 1) & (t.size() - 1);
        t[x] = v;
      }
    table.swap(t);
  }
  std::size_t s = h & (table.size() - 1);
  while (table[s] != kEmpty) s = (s + 1) & (table.size() - 1);
  table[s] = tag | id;
}

}  // namespace

// A run's points, interned in order by themselves: input vertices keep their ids, and the points
// made here get ids from `base` on (the n-th: base + n), translated later (map_) but in the first
// run. With `seeds_apart`, so do the seeded vertices: an earlier run may have a point there.
// (Aligned to a cache line: the runs run side by side, and each writes its own all along.)
struct alignas(64) InternRun {
  InternRun(const Soup* s, Points* p, u32 b) : soup(s), pts(p), base(b) {}
  const Soup* soup;
  Points* pts;
  u32 base;
  // The first run adds its points to `pts` itself (their ids final); the others keep theirs here.
  // (The runs read no point of `pts` meanwhile: exact_position() reads the soup only.)
  bool direct = false;
  Table table = Table(1024, kEmpty);
  std::size_t keys = 0;
  KeptVector<PointDef> defs;  // per point made: its canonical definition (not where direct)
  KeptVector<Vec3> at;        // per point made: its position where interned by position
  KeptVector<char> placed;    // whether it was
  bool seeds_apart = false;    // seeded vertices get ids of their own (to translate), not theirs

  const Vec3& position(u32 id) const { return id < soup->verts.size() ? soup->verts[id] : at[id - base]; }
  std::uint64_t rehash(std::uint64_t v) const {
    const u32 id = static_cast<u32>(v);
    return (v & kPlaceBit) ? position_hash(position(id)) : def_hash(*soup, def(id));
  }
  PointDef def(u32 id) const { return direct ? pts->def(id) : defs[id - base]; }
  u32 find(std::uint64_t h, bool by_position, const PointDef& d, const Vec3& p) const {
    return lookup(table, h, by_position,
                  [&](u32 id) { return by_position ? position(id) == p : same_def(*soup, def(id), d); });
  }
  // The id of a key (a position p, with d its raw definition; or a canonical definition d), made
  // if new (a position as vertex `vertex` where given).
  u32 intern(std::uint64_t h, bool by_position, const PointDef& d, const Vec3& p, u32 vertex = kNone) {
    u32 id = find(h, by_position, d, p);
    if (id != kNone) return id;
    if (vertex != kNone && !seeds_apart) {
      id = vertex;
    } else if (vertex != kNone) {
      // An earlier run may have a point here already: a point of its own, translated later.
      id = base + static_cast<u32>(at.size());
      PointDef v;
      v.p = vertex;
      defs.push_back(v);
      at.push_back(p);
      placed.push_back(1);
    } else {
      id = base + static_cast<u32>(at.size());
      const PointDef c = by_position ? canonical(*soup, d) : d;  // (d: the raw definition where by position)
      if (direct) pts->add_later(c);
      else defs.push_back(c);
      at.push_back(by_position ? p : Vec3(0, 0, 0));
      placed.push_back(by_position);
    }
    put(table, keys, h, tag_of(h, by_position), id, [&](std::uint64_t v) { return rehash(v); });
    return id;
  }
  u32 operator()(const PointDef& raw) {
    if (raw.kind == PointDef::Explicit) return raw.p;
    Vec3 p;
    if (pts->exact_position(raw, p)) return intern(position_hash(p), true, raw, p);
    const PointDef d = canonical(*soup, raw);
    return intern(def_hash(*soup, d), false, d, p);
  }
};


Interner::Interner(Points& pts) : pts_(pts), base_(static_cast<u32>(pts.size())) { table_.assign(1024, kEmpty); }
Interner::~Interner() = default;

const Vec3& Interner::position(u32 id) const {
  return id < pts_.soup().verts.size() ? pts_.soup().verts[id] : at_[id - base_];
}

u32 Interner::operator()(const PointDef& raw) {
  if (raw.kind == PointDef::Explicit) return raw.p;
  Vec3 at;
  if (pts_.exact_position(raw, at)) return find(position_hash(at), true, raw, at);
  const PointDef d = canonical(pts_.soup(), raw);
  return find(def_hash(pts_.soup(), d), false, d, at);
}

// The id of key (h, by_position: at, else the canonical definition d), made if new.
u32 Interner::find(std::uint64_t h, bool by_position, const PointDef& d, const Vec3& at) {
  u32 id = lookup(table_, h, by_position,
                  [&](u32 e) { return by_position ? position(e) == at : same_def(pts_.soup(), pts_.def(e), d); });
  if (id != kNone) return id;
  for (std::size_t r = 1; r < runs_.size(); ++r) {
    id = runs_[r].find(h, by_position, d, at);
    if (id != kNone) return id < base_ ? id : map_[r][id - base_];
  }
  id = pts_.add_later(by_position ? canonical(pts_.soup(), d) : d);
  at_.push_back(by_position ? at : Vec3(0, 0, 0));
  put(table_, keys_, h, tag_of(h, by_position), id, [&](std::uint64_t v) {
    const u32 e = static_cast<u32>(v);
    return (v & kPlaceBit) ? position_hash(position(e)) : def_hash(pts_.soup(), pts_.def(e));
  });
  return id;
}

void Interner::intern_cuts(const std::vector<std::array<u32, 2>>& pairs, const std::vector<PairCutView>& cuts,
                           std::vector<u32>& slot, std::vector<u32>& touched, Works& work) {
  const Soup& soup = pts_.soup();
  const std::size_t np = pairs.size(), nt = soup.tris.size();

  // 1. The runs, each interned in order by itself as the serial pass would (the first run's work
  //    in place).
  base_ = static_cast<u32>(pts_.size());
  const std::size_t runs =
      np < 2048 ? 1 : std::min<std::size_t>(8, thread_count());
  runs_.assign(runs, InternRun(&soup, &pts_, base_));
  runs_[0].direct = true;
  map_.assign(runs, {});
  // Where the runs start: about as many points each, judged from every 8th pair (which sizes
  // the tables too: most points are met twice or more).
  std::vector<std::size_t> start(runs + 1, np);
  start[0] = 0;
  const std::size_t nb = (np + kBlock - 1) / kBlock;
  std::vector<std::size_t> weight(nb + 1, 0);
  parallel_for(0, nb, [&](std::size_t b) {
    std::size_t sum = 0;
    for (std::size_t i = b * kBlock, e = std::min(np, i + kBlock); i < e; i += 8)
      sum += 2 * (cuts[i].segs_t.size() + cuts[i].segs_u.size()) + cuts[i].points.size();
    weight[b + 1] = 8 * sum;
  });
  for (std::size_t b = 0; b < nb; ++b) weight[b + 1] += weight[b];
  for (std::size_t r = 1, b = 0; r < runs; ++r) {
    while (b < nb && weight[b] * runs < weight[nb] * r) ++b;
    start[r] = std::max(start[r - 1], std::min(np, b * kBlock));
  }
  pts_.reserve(base_ + weight[nb] / 2 + 16);  // (room for all runs' points: no copy when joined)
  // Per run but the first: per triangle, its work (kNone); per work, its triangle; the work.
  struct alignas(64) Gathered {
    std::vector<u32> of, tris;
    Works work;
  };
  std::vector<Gathered> gathered(runs);
  slot.assign(nt, kNone);
  touched.clear();
  work.clear();
  parallel_for(0, runs, [&](std::size_t r) {
    InternRun& in = runs_[r];
    in.seeds_apart = r > 0;
    std::vector<u32>& of = r == 0 ? slot : gathered[r].of;
    std::vector<u32>& tris = r == 0 ? touched : gathered[r].tris;
    Works& lw = r == 0 ? work : gathered[r].work;
    if (r > 0) of.assign(nt, kNone);
    const std::size_t from = start[r], to = start[r + 1];
    lw.reserve(std::min(nt, 2 * (to - from)));  // (at most: no copies while the works grow)
    {
      const std::size_t expected = (weight[(to + kBlock - 1) / kBlock] - weight[from / kBlock]) / 2;
      std::size_t size = 1024;
      while (size < 2 * expected) size *= 2;
      in.table.assign(size, kEmpty);
      if (r > 0) {  // (about one new point per four occurrences)
        in.defs.reserve(expected / 2);
        in.at.reserve(expected / 2);
        in.placed.reserve(expected / 2);
      }
    }
    auto wk = [&](u32 t) -> TriWork& {
      if (of[t] == kNone) {
        of[t] = static_cast<u32>(lw.size());
        tris.push_back(t);
        lw.emplace_back();
      }
      return lw[of[t]];
    };
    const PointDef none;
    for (std::size_t i = from; i < to; ++i) {
      if (i % 4096 == 0) soup.poll();
      const PairCutView& c = cuts[i];
      if (c.segs_t.empty() && c.segs_u.empty() && c.points.empty() && !c.coplanar) continue;
      const u32 t = pairs[i][0], u = pairs[i][1];
      // A triangle's first cut seeds its vertices into the positions.
      for (u32 x : {t, u})
        if (of[x] == kNone && (!(x == t ? c.segs_t : c.segs_u).empty() || !c.points.empty() || c.coplanar)) {
          wk(x);
          for (u32 v : soup.tris[x]) in.intern(position_hash(soup.verts[v]), true, none, soup.verts[v], v);
        }
      auto add_segments = [&](std::span<const Segment> segs, u32 tri) {
        for (const auto& s : segs) {
          const u32 a = in(s.a), b = in(s.b);
          TriWork& w = wk(tri);
          w.segs.push_back({a, b});
          w.cuts.push_back(s.cut);
          w.points.push_back(a);
          w.points.push_back(b);
        }
      };
      add_segments(c.segs_t, t);
      add_segments(c.segs_u, u);
      for (const auto& p : c.points) {
        const u32 id = in(p);
        wk(t).points.push_back(id);
        wk(u).points.push_back(id);
      }
      if (c.coplanar) {
        wk(t).coplanar.push_back(u);
        wk(u).coplanar.push_back(t);
      }
    }
  });

  // 2. The other runs' keys in order: a key met in an earlier run has that run's id; the others
  //    are new points (numbered on from the earlier runs' points, in order) or input vertices
  //    seeded there. The first run's table holds final ids: it is table_ from here on.
  at_ = std::move(runs_[0].at);
  table_ = std::move(runs_[0].table);
  keys_ = runs_[0].keys;
  {
    std::size_t all = 0;
    for (const InternRun& in : runs_) all += in.defs.size();
    pts_.reserve(pts_.size() + all + 16);
    at_.reserve(at_.size() + all);
  }
  for (std::size_t r = 1; r < runs; ++r) {
    const InternRun& in = runs_[r];
    auto& m = map_[r];
    m.assign(in.defs.size(), kNone);
    blocks(soup, in.defs.size(), [&](std::size_t n) {
      const PointDef& d = in.defs[n];
      const Vec3& p = in.at[n];
      const bool by_position = in.placed[n];
      const std::uint64_t h = by_position ? position_hash(p) : def_hash(soup, d);
      u32 id = lookup(table_, h, by_position,
                      [&](u32 e) { return by_position ? position(e) == p : same_def(pts_.soup(), pts_.def(e), d); });
      for (std::size_t q = 1; q < r && id == kNone; ++q) {
        id = runs_[q].find(h, by_position, d, p);
        if (id != kNone && id >= base_) id = map_[q][id - base_];
      }
      m[n] = id != kNone || d.kind != PointDef::Explicit ? id : d.p;  // (a seeded vertex, first here)
    });
    for (std::size_t n = 0; n < in.defs.size(); ++n) {
      if ((n & 0xffff) == 0) soup.poll();
      if (m[n] != kNone) continue;
      m[n] = pts_.add_later(in.defs[n]);
      at_.push_back(in.at[n]);
    }
  }

  // 3. Each triangle's work: the runs' in order, in the ids above; the triangles first cut in a
  //    later run follow the earlier runs' in that order. (A run adds to each triangle once.)
  {
    std::size_t all = work.size();
    for (const Gathered& g : gathered) all += g.work.size();
    work.reserve(all);
  }
  for (std::size_t r = 1; r < runs; ++r) {
    Gathered& g = gathered[r];
    for (u32 x : g.tris)
      if (slot[x] == kNone) {
        slot[x] = static_cast<u32>(touched.size());
        touched.push_back(x);
      }
    work.resize(touched.size());
    const auto& m = map_[r];
    blocks(soup, g.work.size(), [&](std::size_t l) {
      TriWork& in = g.work[l];
      auto tr = [&](u32& id) {
        if (id >= base_) id = m[id - base_];
      };
      for (auto& s : in.segs) {
        tr(s[0]);
        tr(s[1]);
      }
      for (auto& p : in.points) tr(p);
      TriWork& out = work[slot[g.tris[l]]];
      if (out.segs.empty() && out.points.empty() && out.coplanar.empty()) {  // nothing from earlier runs
        out = std::move(in);
        return;
      }
      out.segs.insert(out.segs.end(), in.segs.begin(), in.segs.end());
      out.cuts.insert(out.cuts.end(), in.cuts.begin(), in.cuts.end());
      out.points.insert(out.points.end(), in.points.begin(), in.points.end());
      out.coplanar.insert(out.coplanar.end(), in.coplanar.begin(), in.coplanar.end());
    });
  }
}

}  // namespace wedge::boolean_detail
