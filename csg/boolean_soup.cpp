// The boolean engine's input soup: the operands' positions welded into one vertex set (make_soup),
// each triangle's projection axis, zero-area triangles mended, and the edge records sorted.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <numeric>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge {

using namespace boolean_detail;
// Doubles of small integers have all-zero low bits: each coordinate is multiplied by its own odd
// constant and every bit of the sum mixed down (splitmix64's finaliser), so both a hash's low bits
// and its high bits pick a table slot well.
std::uint64_t boolean_detail::position_hash(const Vec3& at) {
  auto bits = [](double x) {
    std::uint64_t b;
    x += 0.0;  // -0 is 0
    std::memcpy(&b, &x, sizeof b);
    return b;
  };
  std::uint64_t z = bits(at.x()) * 0x9e3779b97f4a7c15ull ^ bits(at.y()) * 0xc2b2ae3d27d4eb4full ^
                    bits(at.z()) * 0x165667b19e3779f9ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

std::vector<u32> boolean_detail::operand_starts(const Soup& s) {
  std::vector<u32> first(static_cast<std::size_t>(s.operands) + 1, 0);
  for (int j = 0; j < s.operands; ++j)
    first[j + 1] = static_cast<u32>(
        std::partition_point(s.operand.begin(), s.operand.end(), [&](std::int32_t o) { return o <= j; }) - s.operand.begin());
  return first;
}

std::vector<std::array<double, 6>> boolean_detail::operand_boxes(const Soup& s) {
  const int nops = s.operands;
  std::vector<std::array<double, 6>> box(nops, {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY});
  // Per block of triangles, then merged (min and max: the same at any thread count).
  constexpr std::size_t kBlock = 65536;
  const std::size_t nt = s.tris.size();
  std::vector<std::vector<std::array<double, 6>>> part((nt + kBlock - 1) / kBlock, box);
  parallel_blocks(nt, kBlock, [&](std::size_t from, std::size_t to) {
    for (std::size_t t = from; t < to; ++t) {
      double lo[3], hi[3];
      triangle_box(s, static_cast<u32>(t), lo, hi);
      auto& b = part[from / kBlock][s.operand[t]];
      for (int d = 0; d < 3; ++d) {
        b[d] = std::min(b[d], lo[d]);
        b[d + 3] = std::max(b[d + 3], hi[d]);
      }
    }
  });
  for (const auto& p : part)
    for (int j = 0; j < nops; ++j)
      for (int d = 0; d < 3; ++d) {
        box[j][d] = std::min(box[j][d], p[j][d]);
        box[j][d + 3] = std::max(box[j][d + 3], p[j][d + 3]);
      }
  return box;
}

// Merges the operands into one soup of triangles on unique positions. Equal positions become one
// vertex, numbered in the order of their first use (operand by operand, position by position):
// the same numbering at any thread count. In parallel over blocks of positions: each position
// goes into an open-addressing table (linear probing) of (hash tag, lowest index of the class),
// inserted or lowered by compare-and-swap; a class never moves once in the table, so every
// position finds its class where it put it. The table is touched at random (a miss per
// position, 1M of them for two 1M-triangle spheres), so each block looks its slots up 16 ahead.
// Only positions whose class another index holds (a duplicate, or one whose entry a lower
// duplicate took over) look it up there again: the rest are their classes' first (a second miss
// per position was 15 of those spheres' 72 ms).
Soup boolean_detail::make_soup(const std::vector<const Mesh*>& operands, const Interrupt* interrupt) {
  Soup s;
  s.interrupt = interrupt;
  s.operands = static_cast<int>(operands.size());
  const std::size_t nops = operands.size();
  std::vector<std::size_t> vbase(nops + 1, 0), tbase(nops + 1, 0);
  for (std::size_t o = 0; o < nops; ++o) {
    vbase[o + 1] = vbase[o] + operands[o]->positions.size();
    tbase[o + 1] = tbase[o] + operands[o]->triangles.size();
  }
  const std::size_t np = vbase[nops], nt = tbase[nops];
  if (np >= (std::size_t(1) << 31)) fail("boolean: more than 2^31 positions in the operands");
  // Every position, -0 made 0 (so that equal positions have equal bits), with its hash; and
  // each operand's box, per block of its positions, merged in order below.
  std::vector<Vec3, NoInit<Vec3>> all(np);
  std::vector<std::uint64_t, NoInit<std::uint64_t>> hash(np);
  constexpr std::size_t kBlock = 1 << 14;
  std::vector<std::size_t> bbase(nops + 1, 0);
  for (std::size_t o = 0; o < nops; ++o) bbase[o + 1] = bbase[o] + (operands[o]->positions.size() + kBlock - 1) / kBlock;
  constexpr std::array<double, 6> kNoBox = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  std::vector<std::array<double, 6>> part(bbase[nops], kNoBox);
  parallel_for(0, nops, [&](std::size_t o) {
    const Mesh& m = *operands[o];
    parallel_blocks(m.positions.size(), kBlock, [&](std::size_t lo, std::size_t hi) {
      std::array<double, 6> b = kNoBox;
      for (std::size_t v = lo; v < hi; ++v) {
        Vec3 p = m.positions[v];
        for (int i = 0; i < 3; ++i) {
          if (p[i] == 0) p[i] = 0.0;
          b[i] = std::min(b[i], p[i]);
          b[i + 3] = std::max(b[i + 3], p[i]);
        }
        all[vbase[o] + v] = p;
        hash[vbase[o] + v] = position_hash(p);
      }
      part[bbase[o] + lo / kBlock] = b;
    });
  });
  s.boxes.assign(nops, kNoBox);
  for (std::size_t o = 0; o < nops; ++o)
    if (!operands[o]->triangles.empty())
      for (std::size_t k = bbase[o]; k < bbase[o + 1]; ++k)
        for (int i = 0; i < 3; ++i) {
          s.boxes[o][i] = std::min(s.boxes[o][i], part[k][i]);
          s.boxes[o][i + 3] = std::max(s.boxes[o][i + 3], part[k][i + 3]);
        }
  s.poll();
  int bits = 4;
  while ((std::size_t(1) << bits) < 2 * np) ++bits;
  // An entry: the hash's low 32 bits (a tag that settles most mismatches without reading the
  // position) and the class's lowest index; kEmpty where free.
  constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  // (Raw words under atomic_ref: a vector of atomics would be zeroed first, serially.)
  std::vector<std::uint64_t, NoInit<std::uint64_t>> table(std::size_t(1) << bits);
  auto entry = [&](std::size_t i) { return std::atomic_ref<std::uint64_t>(table[i]); };
  parallel_blocks(table.size(), kBlock, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) table[i] = kEmpty;
  });
  const std::size_t mask = table.size() - 1;
  std::vector<u32, NoInit<u32>> slot_of(np);
  std::vector<char> lookup(np, 0);  // a position whose class is held by another index
  parallel_blocks(np, kBlock, [&](std::size_t lo, std::size_t end) {
    s.poll();
    constexpr std::size_t kAhead = 16;
    for (std::size_t g = lo; g < std::min(end, lo + kAhead); ++g) __builtin_prefetch(&table[hash[g] >> (64 - bits)]);
    for (std::size_t g = lo; g < end; ++g) {
      if (g + kAhead < end) __builtin_prefetch(&table[hash[g + kAhead] >> (64 - bits)]);
      const std::uint64_t tag = hash[g] & 0xffffffffu;
      const std::uint64_t mine = tag << 32 | g;
      std::size_t slot = hash[g] >> (64 - bits);
      for (;;) {
        std::uint64_t cur = entry(slot).load(std::memory_order_relaxed);
        if (cur == kEmpty) {
          if (entry(slot).compare_exchange_strong(cur, mine, std::memory_order_relaxed)) break;
          // Taken meanwhile: cur now holds what is there; look at it below.
        }
        if ((cur >> 32) == tag && all[cur & 0xffffffffu] == all[g]) {
          // g's class: keep its lowest index. The index it replaces, or g where a lower one
          // holds the class, will look its class up in the table; the others hold their own.
          std::size_t was = g;
          while ((cur & 0xffffffffu) > g) {
            if (entry(slot).compare_exchange_weak(cur, mine, std::memory_order_relaxed)) {
              was = cur & 0xffffffffu;
              break;
            }
          }
          std::atomic_ref<char>(lookup[was]).store(1, std::memory_order_relaxed);
          break;
        }
        slot = (slot + 1) & mask;
      }
      slot_of[g] = static_cast<u32>(slot);
    }
  });
  s.poll();
  // Each position's class (its lowest index), and the classes numbered in the order of their
  // first positions: a count per block, then the blocks' offsets.
  std::vector<u32, NoInit<u32>> rep(np);
  const auto firsts = block_starts(np, kBlock, [&](std::size_t lo, std::size_t hi) {
    std::size_t n = 0;
    for (std::size_t g = lo; g < hi; ++g) {
      rep[g] = lookup[g] ? static_cast<u32>(table[slot_of[g]] & 0xffffffffu) : static_cast<u32>(g);
      n += rep[g] == g;
    }
    return n;
  });
  s.verts.resize(firsts.total());
  std::vector<u32, NoInit<u32>> id(np);
  // The operand of position g.
  auto operand_of = [&](std::size_t g) {
    return static_cast<std::int32_t>(std::upper_bound(vbase.begin(), vbase.end(), g) - vbase.begin() - 1);
  };
  s.vertex_operand.resize(s.verts.size());
  fill_blocks(firsts, [&](std::size_t lo, std::size_t hi, std::size_t next) {
    std::int32_t op = operand_of(lo);
    for (std::size_t g = lo; g < hi; ++g) {
      while (g >= vbase[op + 1]) ++op;
      if (rep[g] == g) {
        s.verts[next] = all[g];
        s.vertex_operand[next] = op;
        id[g] = static_cast<u32>(next++);
      }
    }
  });
  // A class's index is its first position's, which precedes every other of its positions; a
  // class with positions of two operands is marked -2.
  parallel_blocks(np, kBlock, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t g = lo; g < hi; ++g)
      if (rep[g] != g) {
        id[g] = id[rep[g]];
        if (operand_of(g) != operand_of(rep[g]))
          std::atomic_ref<std::int32_t>(s.vertex_operand[id[g]]).store(-2, std::memory_order_relaxed);
      }
  });
  s.poll();
  s.tris.resize(nt);
  s.operand.resize(nt);
  s.local.resize(nt);
  s.face_id.resize(nt);
  parallel_for(0, nops, [&](std::size_t o) {
    const Mesh& m = *operands[o];
    const u32* map = id.data() + vbase[o];
    parallel_blocks(m.triangles.size(), kBlock, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t t = lo; t < hi; ++t) {
        const auto& tr = m.triangles[t];
        const std::size_t x = tbase[o] + t;
        s.tris[x] = {map[tr[0]], map[tr[1]], map[tr[2]]};
        s.operand[x] = static_cast<std::int32_t>(o);
        s.local[x] = static_cast<std::int32_t>(t);
        s.face_id[x] = m.face_ids.empty() ? -1 : m.face_ids[t];
      }
    });
  });
  s.axis.resize(nt);
  s.axis_sign.resize(nt);
  parallel_for(0, nt, [&](std::size_t t) { set_axis(s, t); });
  return s;
}

// k(T): the axis along which triangle t's normal is largest whose projection is not flat, and
// the sign of its normal there; -1 when t has zero area.
void boolean_detail::set_axis(Soup& s, std::size_t t) {
  const auto& T = s.tris[t];
  const Vec3 &a = s.verts[T[0]], &b = s.verts[T[1]], &c = s.verts[T[2]];
  // The common case without branches on the axes' order (a sphere's triangles take them at
  // random): the axis of the largest |n_k| (the lowest of equals), whose normal component is the
  // projection's orient2d, l_k - r_k, decided by orient2d_fast's filter as it would be there.
  const Vec3 u = b - a, w = c - a;
  const double l[3] = {u[1] * w[2], u[2] * w[0], u[0] * w[1]}, r[3] = {u[2] * w[1], u[0] * w[2], u[1] * w[0]};
  const double d[3] = {l[0] - r[0], l[1] - r[1], l[2] - r[2]};
  const double m0 = std::abs(d[0]), m1 = std::abs(d[1]), m2 = std::abs(d[2]);
  int k = m1 > m0 ? 1 : 0;
  k = m2 > std::max(m0, m1) ? 2 : k;
  if (const int o = orient2d_filter(l[k], r[k])) {
    s.axis[t] = static_cast<std::int8_t>(k);
    s.axis_sign[t] = static_cast<std::int8_t>(o);
    return;
  }
  const Vec3 nrm = u.cross(w);
  // The axes by decreasing |n| (ties in axis order, as a stable sort of 0, 1, 2 would give).
  const double n0 = std::abs(nrm[0]), n1 = std::abs(nrm[1]), n2 = std::abs(nrm[2]);
  int order[3] = {0, 1, 2};
  if (n1 > n0) std::swap(order[0], order[1]);
  const double first = std::max(n0, n1), second = std::min(n0, n1);
  if (n2 > first) order[2] = order[1], order[1] = order[0], order[0] = 2;
  else if (n2 > second) order[2] = order[1], order[1] = 2;
  s.axis[t] = -1;
  s.axis_sign[t] = 0;
  for (int k : order) {
    int i = (k + 1) % 3, j = (k + 2) % 3;
    int o = orient2d_fast(a[i], a[j], b[i], b[j], c[i], c[j]);
    if (o != 0) {
      s.axis[t] = static_cast<std::int8_t>(k);
      s.axis_sign[t] = static_cast<std::int8_t>(o);
      break;
    }
  }
}

// Mends the zero-area triangles of the operands marked in `check` where that moves no point of
// the surface. A triangle with two corners at one vertex is dropped: its other two edges' twins
// become each other's. A flat triangle x, m, y (m inside the segment from x to y) is made from
// its neighbour x, y, d across the long edge: the two become x, m, d and m, y, d, the same
// points as before (meshes rounded to floats, as STL files are, have such slivers). A flat
// triangle whose neighbour is flat too, or whose long edge has no one neighbour, is left for
// soup_defects to report. The mended triangles keep the neighbour's provenance.
void boolean_detail::mend_flat_triangles(Soup& s, const std::vector<char>& check) {
  std::vector<u32> flat;
  for (std::size_t t = 0; t < s.tris.size(); ++t)
    if (s.axis[t] < 0 && check[static_cast<std::size_t>(s.operand[t])]) flat.push_back(static_cast<u32>(t));
  if (flat.empty()) return;
  std::vector<char> removed(s.tris.size(), 0), operand_hit(static_cast<std::size_t>(s.operands), 0);
  for (u32 t : flat) operand_hit[static_cast<std::size_t>(s.operand[t])] = 1;
  auto key = [](u32 a, u32 b) { return static_cast<std::uint64_t>(a) << 32 | b; };
  bool any_removed = false;
  // Each round mends the flat triangles whose neighbour is not flat (a chain of flat neighbours
  // takes a round a link); each scans the operands' triangles once, so rounds are capped: what a
  // longer chain leaves is reported.
  int rounds = 0;
  for (bool progress = true; progress && !flat.empty() && rounds < 64; ++rounds) {
    progress = false;
    s.poll();
    // Each flat triangle's wanted neighbour edge x -> y (its own long edge reversed).
    struct Want {
      u32 t, x, m, y;
      u32 found = kNone;
      int count = 0;
    };
    std::vector<Want> want;
    std::unordered_multimap<std::uint64_t, std::size_t> by_edge;
    for (u32 t : flat) {
      const auto& T = s.tris[t];
      if (T[0] == T[1] || T[1] == T[2] || T[0] == T[2]) {
        removed[t] = 1;  // two corners at one vertex
        any_removed = progress = true;
        continue;
      }
      // The middle corner: along the axis of the largest extent the three coordinates differ.
      int k = 0;
      double ext = -1;
      for (int d = 0; d < 3; ++d) {
        const double lo = std::min({s.verts[T[0]][d], s.verts[T[1]][d], s.verts[T[2]][d]});
        const double hi = std::max({s.verts[T[0]][d], s.verts[T[1]][d], s.verts[T[2]][d]});
        if (hi - lo > ext) ext = hi - lo, k = d;
      }
      int mid = 0;
      for (int c = 0; c < 3; ++c) {
        const double v = s.verts[T[c]][k], p = s.verts[T[(c + 1) % 3]][k], q = s.verts[T[(c + 2) % 3]][k];
        if ((p < v && v < q) || (q < v && v < p)) mid = c;
      }
      Want w{t, T[(mid + 2) % 3], T[mid], T[(mid + 1) % 3]};
      by_edge.emplace(key(w.x, w.y), want.size());
      want.push_back(w);
    }
    // The triangles with those edges, in the same operands.
    for (std::size_t u = 0; u < s.tris.size(); ++u) {
      if (removed[u] || !operand_hit[static_cast<std::size_t>(s.operand[u])]) continue;
      const auto& U = s.tris[u];
      for (int c = 0; c < 3; ++c) {
        auto [lo, hi] = by_edge.equal_range(key(U[c], U[(c + 1) % 3]));
        for (auto it = lo; it != hi; ++it) {
          Want& w = want[it->second];
          if (s.operand[u] != s.operand[w.t]) continue;
          w.found = static_cast<u32>(u);
          ++w.count;
        }
      }
    }
    std::vector<char> touched(s.tris.size(), 0);
    flat.clear();
    for (const Want& w : want) {
      const u32 n = w.found;
      if (w.count != 1 || touched[w.t] || touched[n] || removed[n]) {
        if (w.count == 1 && !removed[w.t]) flat.push_back(w.t);  // again, next round
        continue;
      }
      const auto& N = s.tris[n];
      int at = 0;
      while (N[at] != w.x) ++at;
      const u32 d = N[(at + 2) % 3];
      if (d == w.m) {
        // The neighbour is the same three vertices the other way round: the two bound nothing.
        removed[w.t] = removed[n] = 1;
        any_removed = progress = true;
        continue;
      }
      if (s.axis[n] < 0) {  // flat too: perhaps mended first this round
        flat.push_back(w.t);
        continue;
      }
      s.tris[w.t] = {w.x, w.m, d};
      s.tris[n] = {w.m, w.y, d};
      s.local[w.t] = s.local[n];
      s.face_id[w.t] = s.face_id[n];
      set_axis(s, w.t);
      set_axis(s, n);
      touched[w.t] = touched[n] = 1;
      progress = true;
    }
  }
  if (!any_removed) return;
  std::size_t k = 0;
  for (std::size_t t = 0; t < s.tris.size(); ++t) {
    if (removed[t]) continue;
    s.tris[k] = s.tris[t];
    s.operand[k] = s.operand[t];
    s.local[k] = s.local[t];
    s.face_id[k] = s.face_id[t];
    s.axis[k] = s.axis[t];
    s.axis_sign[k] = s.axis_sign[t];
    ++k;
  }
  s.tris.resize(k);
  s.operand.resize(k);
  s.local.resize(k);
  s.face_id.resize(k);
  s.axis.resize(k);
  s.axis_sign.resize(k);
}

void boolean_detail::sort_edges(EdgeRecs& recs, std::size_t n, const Interrupt* interrupt) {
  auto poll = [&] {
    if (interrupt) interrupt->poll();
  };
  poll();
  if (recs.size() < n / 4) {
    // Few records among many points (two 1M-triangle spheres' difference pairs most edges
    // directly: 36,654 records over 1,056,628 points), where counting over every point was most of
    // the work: the keys radix-sorted, then each run of one key put in value order (its values
    // alone move: the keys, which for_each_run reads across blocks, are all the run's one).
    radix_sort(recs, [](const EdgeRec& r) { return r.key; });
    for_each_run(recs, interrupt, [&](std::size_t i, std::size_t j) {
      for (std::size_t a = i + 1; a < j; ++a)
        for (std::size_t b = a; b > i && recs[b].value < recs[b - 1].value; --b) std::swap(recs[b].value, recs[b - 1].value);
    });
    return;
  }
  // A counting sort by the first vertex. Over a few chunks of the records at once: chunk c's
  // records of vertex v go after chunks 0..c-1's (the order within a vertex is settled by the
  // sort below in any case).
  const std::size_t m = recs.size();
  const std::size_t chunks =
      m < (std::size_t(1) << 16) ? 1 : std::min<std::size_t>(8, thread_count());
  const std::size_t per = (m + chunks - 1) / chunks;
  std::vector<std::vector<u32>> next(chunks);
  parallel_for(0, chunks, [&](std::size_t c) {
    next[c].assign(n, 0);
    for (std::size_t r = c * per; r < std::min(m, (c + 1) * per); ++r) ++next[c][recs[r].key >> 32];
  });
  poll();
  std::vector<u32, NoInit<u32>> off(n + 1);
  chunk_offsets(next, n, off);
  EdgeRecs out(m);
  poll();
  parallel_for(0, chunks, [&](std::size_t c) {
    std::vector<u32>& at = next[c];
    for (std::size_t r = c * per; r < std::min(m, (c + 1) * per); ++r) out[at[recs[r].key >> 32]++] = recs[r];
  });
  next.clear();
  poll();
  auto less = [](const EdgeRec& x, const EdgeRec& y) { return x.key < y.key || (x.key == y.key && x.value < y.value); };
  parallel_blocks(n, 4096, [&](std::size_t lo, std::size_t hi) {
    poll();
    for (std::size_t v = lo; v < hi; ++v) {
      EdgeRec* first = out.data() + off[v];
      EdgeRec* last = out.data() + off[v + 1];
      if (last - first <= 16) {
        for (EdgeRec* i = first + 1; i < last; ++i)  // insertion sort: a vertex has a few edges
          for (EdgeRec* j = i; j > first && less(*j, *(j - 1)); --j) std::swap(*j, *(j - 1));
      } else {
        std::sort(first, last, less);
      }
    }
  });
  recs.swap(out);
}

}  // namespace wedge
