// The vertex stage (GL 1.x sections 2.10-2.14): eye coordinates, the eye normal by the inverse
// transpose of the modelview, texture coordinates (texgen, texture matrix), the fog distance and
// the lighting equation of 2.14.1 in float, as GL implementations light:
//   c = emission + ambient * model ambient
//       + sum over lights of att * spot * (ambient + max(n.VP, 0) diffuse + f specular),
//   f = max(n.h, 0)^shininess (h: VP + the eye direction, normalised), clamped to [0, 1].
// light_vertex is the scalar form (the general path and per-pixel Phong); the batched triangle
// path lights 4 vertices at a time (F4, SSE2) or 16 (F16 = two F8, AVX2) with the same float
// operations in the same order lane by lane (light_t), so every lane gives light_vertex's bits.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

// The lighting equation of GL 1.x section 2.14.1 for one side, in float. P is the eye-space
// position, n the unit (or as given) eye-space normal; `vertex_color` feeds colour material.
// pow only for a positive specular term with non-zero shininess, as GL defines 0^0 = 1.
Vec4f light_vertex(const Context::State& s, const LightSetup& ls, const Vec4& P4, const Vec3& nd,
                   const Vec4f& vertex_color, int side) {
  Material m = s.material[side];  // a copy: colour material may replace parts of it
  if (ls.color_material[side]) {
    switch (s.cm_mode) {
      case ColorMaterialMode::Ambient: m.ambient = vertex_color; break;
      case ColorMaterialMode::Diffuse: m.diffuse = vertex_color; break;
      case ColorMaterialMode::Specular: m.specular = vertex_color; break;
      case ColorMaterialMode::Emission: m.emission = vertex_color; break;
      case ColorMaterialMode::AmbientAndDiffuse: m.ambient = m.diffuse = vertex_color; break;
    }
  }
  const Vec3f P = (P4.head<3>() / P4.w()).cast<float>();
  const Vec3f n = nd.cast<float>();
  const Vec3f ma = m.ambient.head<3>(), md = m.diffuse.head<3>(), ms = m.specular.head<3>();
  Vec3f c = m.emission.head<3>() + ma.cwiseProduct(ls.model_ambient);
  Vec3f eye_dir(0, 0, 1);
  if (ls.local_viewer) eye_dir = -P.normalized();
  for (int i = 0; i < ls.n; ++i) {
    const LightSetup::L& L = ls.l[i];
    Vec3f VP;
    float att = 1;
    if (L.local) {
      VP = L.pos - P;
      float d = VP.norm();
      VP /= d;
      att = 1.0f / (L.kc + L.kl * d + L.kq * d * d);
    } else {
      VP = L.pos;
    }
    float spot = 1;
    if (L.spot) {
      float cosang = -VP.dot(L.sdir);
      if (cosang < L.cos_cut) spot = 0;
      else spot = L.sexp == 0 ? 1.0f : gl_pow(std::max(cosang, 0.0f), L.sexp);
    }
    if (att * spot == 0) continue;
    Vec3f term = ma.cwiseProduct(L.amb);
    float ndl = n.dot(VP);
    if (ndl > 0) {
      term += ndl * md.cwiseProduct(L.dif);
      Vec3f h = VP + eye_dir;
      float hn = h.norm();
      if (hn > 0) {
        float ndh = n.dot(h) / hn;
        if (ndh > 0) {
          float f = m.shininess == 0 ? 1.0f : gl_pow(ndh, m.shininess);
          term += f * ms.cwiseProduct(L.spec);
        }
      }
    }
    c += (att * spot) * term;
  }
  Vec4f out(c.x(), c.y(), c.z(), m.diffuse.w());
  return clamp01(out);
}

// light_vertex's per-draw constants broadcast to the lanes of V, with the products of material
// and light colours it forms per vertex (the same float products) made once. Colour material
// replaces material colours by the vertex colours: those products are then formed per block.
template <class V>
struct LightConsts {
  struct Side {
    V me[4], ma[4], md[4], ms[4];
    V base[3];                          // emission + ambient * model ambient
    V amb[8][3], dif[8][3], spec[8][3];  // material * light colours
    float shin = 0;
    bool cm = false;
  };
  struct L {
    V pos[3], sdir[3], lamb[3], ldif[3], lspec[3];
  };
  Side side[2];
  L l[8];
  V model_ambient[3];
  LightConsts(const Context::State& s, const LightSetup& ls) {
    for (int k = 0; k < 3; ++k) model_ambient[k] = splat<V>(ls.model_ambient[k]);
    for (int i = 0; i < ls.n; ++i)
      for (int k = 0; k < 3; ++k) {
        const LightSetup::L& L = ls.l[i];
        l[i].pos[k] = splat<V>(L.pos[k]), l[i].sdir[k] = splat<V>(L.sdir[k]);
        l[i].lamb[k] = splat<V>(L.amb[k]), l[i].ldif[k] = splat<V>(L.dif[k]), l[i].lspec[k] = splat<V>(L.spec[k]);
      }
    for (int sd = 0; sd < (s.two_side ? 2 : 1); ++sd) {  // (the back side is lit only two-sided)
      const Material& m = s.material[sd];
      Side& d = side[sd];
      d.cm = ls.color_material[sd];
      d.shin = m.shininess;
      for (int k = 0; k < 4; ++k)
        d.me[k] = splat<V>(m.emission[k]), d.ma[k] = splat<V>(m.ambient[k]), d.md[k] = splat<V>(m.diffuse[k]),
        d.ms[k] = splat<V>(m.specular[k]);
      for (int k = 0; k < 3; ++k) d.base[k] = d.me[k] + d.ma[k] * model_ambient[k];
      for (int i = 0; i < ls.n; ++i)
        for (int k = 0; k < 3; ++k)
          d.amb[i][k] = d.ma[k] * l[i].lamb[k], d.dif[i][k] = d.md[k] * l[i].ldif[k], d.spec[i][k] = d.ms[k] * l[i].lspec[k];
    }
  }
};

namespace {

// Four (F4) or sixteen (F16) vertices lit at once: light_vertex's float operations in the same
// order, lane by lane, so the colours are the same bits. P: eye positions (divided by w);
// n: normals, negated for the back side; vc: vertex colours (read with colour material only).
// (The loops over components are unrolled by pragmas here, in vpow and in light_needed: left as
// loops, -O2 keeps those small arrays of vectors on the stack, each step a store and a reload.)
template <class V, bool CM>
[[gnu::always_inline]] inline void light_t(const Context::State& s, const LightSetup& ls,
                                           const typename LightConsts<V>::Side& m, const LightConsts<V>& lc,
                                           const V* P, const V* n, const V* vc, V* out) {
  typedef typename Lanes<V>::I I;
  const V *me = m.me, *ma = m.ma, *md = m.md, *ms = m.ms;
  V cme[4], cma[4], cmd[4], cms[4];
  if constexpr (CM) {
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) cme[k] = m.me[k], cma[k] = m.ma[k], cmd[k] = m.md[k], cms[k] = m.ms[k];
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) {
      switch (s.cm_mode) {
        case ColorMaterialMode::Ambient: cma[k] = vc[k]; break;
        case ColorMaterialMode::Diffuse: cmd[k] = vc[k]; break;
        case ColorMaterialMode::Specular: cms[k] = vc[k]; break;
        case ColorMaterialMode::Emission: cme[k] = vc[k]; break;
        case ColorMaterialMode::AmbientAndDiffuse: cma[k] = cmd[k] = vc[k]; break;
      }
    }
    me = cme, ma = cma, md = cmd, ms = cms;
  }
  V c[3];
#pragma GCC unroll 4
  for (int k = 0; k < 3; ++k) c[k] = CM ? me[k] + ma[k] * lc.model_ambient[k] : m.base[k];
  V ed[3] = {splat<V>(0), splat<V>(0), splat<V>(1)};
  if (ls.local_viewer) {
    const V z = dot3(P, P);
    const I pos = z > 0.0f;
    const V r = vsqrt(z);
#pragma GCC unroll 4
    for (int k = 0; k < 3; ++k) ed[k] = sel(pos, -(P[k] / r), -P[k]);
  }
  const float shin = m.shin;
  for (int i = 0; i < ls.n; ++i) {
    const LightSetup::L& L = ls.l[i];
    const typename LightConsts<V>::L& C = lc.l[i];
    V VP[3];
    V att = splat<V>(1);
    if (L.local) {
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) VP[k] = C.pos[k] - P[k];
      const V d = vsqrt(dot3(VP, VP));
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) VP[k] = VP[k] / d;
      att = 1.0f / ((L.kc + L.kl * d) + (L.kq * d) * d);
    } else {
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) VP[k] = C.pos[k];
    }
    V spot = splat<V>(1);
    if (L.spot) {
      const V cosang = -dot3(VP, C.sdir);
      const I in = ~(cosang < L.cos_cut);
      if (L.sexp == 0) spot = sel(in, splat<V>(1), splat<V>(0));
      else spot = sel(in, vpow(sel(cosang < 0.0f, splat<V>(0.0f), cosang), L.sexp), splat<V>(0));  // (std::max)
    }
    const V k = att * spot;
    const I use = ~(k == 0.0f);
    if (!any(use)) continue;
    V amb[3], dif[3], spec[3];
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) {
      amb[q] = CM ? ma[q] * C.lamb[q] : m.amb[i][q];
      dif[q] = CM ? md[q] * C.ldif[q] : m.dif[i][q];
      spec[q] = CM ? ms[q] * C.lspec[q] : m.spec[i][q];
    }
    V term[3];
    const V ndl = dot3(n, VP);
    const I dmask = ndl > 0.0f;
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) term[q] = sel(dmask, amb[q] + ndl * dif[q], amb[q]);
    V h[3];
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) h[q] = VP[q] + ed[q];
    const V hn = vsqrt(dot3(h, h));
    const V ndh = dot3(n, h) / hn;
    const I smask = dmask & (hn > 0.0f) & (ndh > 0.0f);
    if (any(smask)) {
      // (The lanes outside smask compute a pow that is not used.)
      const V f = shin != 0 ? vpow(ndh, shin) : splat<V>(1);
#pragma GCC unroll 4
      for (int q = 0; q < 3; ++q) term[q] = sel(smask, term[q] + f * spec[q], term[q]);
    }
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) c[q] = sel(use, c[q] + k * term[q], c[q]);
  }
#pragma GCC unroll 4
  for (int q = 0; q < 3; ++q) out[q] = vclamp01(c[q]);
  out[3] = vclamp01(md[3]);
}

template <class V>
[[gnu::always_inline]] inline void light(const Context::State& s, const LightSetup& ls, const LightConsts<V>& lc,
                                         const V* P, const V* n, const V* vc, int side, V* out) {
  const typename LightConsts<V>::Side& m = lc.side[side];
  if (m.cm) light_t<V, true>(s, ls, m, lc, P, n, vc, out);
  else light_t<V, false>(s, ls, m, lc, P, n, vc, out);
}

// The two builds, out of line (the equation is inlined once per build and colour-material case).
void light_lanes(const Context::State& s, const LightSetup& ls, const LightConsts<F4>& lc, const F4* P, const F4* n,
                 const F4* vc, int side, F4* out) {
  light<F4>(s, ls, lc, P, n, vc, side, out);
}
#if defined(__x86_64__) && defined(__GNUC__)
typedef X2<F8> F16;  // the AVX2 build's lanes: two groups of eight
__attribute__((target("avx2"))) void light_lanes_avx2(const Context::State& s, const LightSetup& ls,
                                                      const LightConsts<F16>& lc, const F16* P, const F16* n,
                                                      const F16* vc, int side, F16* out) {
  light<F16>(s, ls, lc, P, n, vc, side, out);
}
[[gnu::always_inline]] inline void light_lanes(const Context::State& s, const LightSetup& ls,
                                               const LightConsts<F16>& lc, const F16* P, const F16* n,
                                               const F16* vc, int side, F16* out) {
  light_lanes_avx2(s, ls, lc, P, n, vc, side, out);
}
#endif

// Lanes to vertices: the RGBA of lane l (c: R, G, B, A rows) to a + l * stride, for l < lanes.
[[gnu::always_inline]] inline void store_rgba(const F4* c, float* a, std::size_t stride, std::size_t lanes) {
  const F4 t0 = __builtin_shufflevector(c[0], c[1], 0, 4, 1, 5), t1 = __builtin_shufflevector(c[0], c[1], 2, 6, 3, 7);
  const F4 t2 = __builtin_shufflevector(c[2], c[3], 0, 4, 1, 5), t3 = __builtin_shufflevector(c[2], c[3], 2, 6, 3, 7);
  const F4 v[4] = {__builtin_shufflevector(t0, t2, 0, 1, 4, 5), __builtin_shufflevector(t0, t2, 2, 3, 6, 7),
                   __builtin_shufflevector(t1, t3, 0, 1, 4, 5), __builtin_shufflevector(t1, t3, 2, 3, 6, 7)};
  for (std::size_t l = 0; l < lanes; ++l) std::memcpy(a + l * stride, &v[l], sizeof(F4));
}
[[gnu::always_inline]] inline void store_rgba(const F8* c, float* a, std::size_t stride, std::size_t lanes) {
  // Within each 128-bit half as the four-lane transpose: u[l] holds vertex l, then vertex l + 4.
  const F8 t0 = __builtin_shufflevector(c[0], c[1], 0, 8, 1, 9, 4, 12, 5, 13);
  const F8 t1 = __builtin_shufflevector(c[0], c[1], 2, 10, 3, 11, 6, 14, 7, 15);
  const F8 t2 = __builtin_shufflevector(c[2], c[3], 0, 8, 1, 9, 4, 12, 5, 13);
  const F8 t3 = __builtin_shufflevector(c[2], c[3], 2, 10, 3, 11, 6, 14, 7, 15);
  const F8 u[4] = {__builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13),
                   __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15),
                   __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13),
                   __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15)};
  if (lanes == 8) {
    for (int l = 0; l < 4; ++l) {
      const F4 a0 = lo(u[l]), a1 = hi(u[l]);
      std::memcpy(a + l * stride, &a0, sizeof(F4)), std::memcpy(a + (l + 4) * stride, &a1, sizeof(F4));
    }
    return;
  }
  for (std::size_t l = 0; l < lanes; ++l) {
    const F4 v = l < 4 ? lo(u[l]) : hi(u[l - 4]);
    std::memcpy(a + l * stride, &v, sizeof(F4));
  }
}

[[gnu::always_inline]] inline void store_rgba(const X2<F8>* c, float* a, std::size_t stride, std::size_t lanes) {
  const F8 ca[4] = {c[0].a, c[1].a, c[2].a, c[3].a}, cb[4] = {c[0].b, c[1].b, c[2].b, c[3].b};
  store_rgba(ca, a, stride, std::min<std::size_t>(lanes, 8));
  if (lanes > 8) store_rgba(cb, a + 8 * stride, stride, lanes - 8);
}

// vertex_attrs' eye normal on all lanes (double, m = nmat column-major): nmat * n in Eigen's order for a
// Matrix3d times a Vector3d (rows 0 and 1 as (m0 n0 + m1 n1) + m2 n2, row 2 as m0 n0 + (m1 n1 +
// m2 n2)), divided by its norm sqrt((x x + y y) + z z) when normalising and the norm is positive.
template <class D>
[[gnu::always_inline]] inline void eye_normals(const double* m, D* n, bool normalize) {
  const D r0 = (m[0] * n[0] + m[3] * n[1]) + m[6] * n[2];
  const D r1 = (m[1] * n[0] + m[4] * n[1]) + m[7] * n[2];
  const D r2 = m[2] * n[0] + (m[5] * n[1] + m[8] * n[2]);
  n[0] = r0, n[1] = r1, n[2] = r2;
  if (normalize) {
    const D len = vsqrt((r0 * r0 + r1 * r1) + r2 * r2);
    for (int k = 0; k < 3; ++k) n[k] = sel(len > 0.0, n[k] / len, n[k]);
  }
}

// The lighting's inputs for needed vertices q .. q + lanes - 1 (lanes <= W), gathered by rows (SoA,
// in registers; a run of consecutive vertices is read straight from the eye rows, and, from packed
// client normals `nrm`, as three vectors per half), the eye position divided by w and the normal
// transformed and normalised in double on all lanes at once with vertex_attrs' operations
// (eye_normals). Unless `lean`, vertex_attrs' other attributes go to attrs.
template <class V, class Src>
[[gnu::always_inline]] inline void light_inputs(const Context::State& s, const Src& src, const Mat3& nmat,
                                                const double* m, const double* nrm, const NeededVerts& nv,
                                                std::size_t q, std::size_t lanes, bool lean, bool want_color,
                                                const AttrNeeds& needs, float* attrs, std::size_t astride, V* P,
                                                V* N, V* C) {
  constexpr int W = Lanes<V>::W, H = W / 2;
  typedef typename Lanes<V>::D D;
  const bool normalize = s.on(Cap::Normalize);
  const std::uint32_t* nd = nv.need + q;
  // The lanes' vertices (the last group's unused lanes repeat lane 0's: computed, not stored).
  std::uint32_t idx[W];
  for (int l = 0; l < W; ++l) idx[l] = nd[std::size_t(l) < lanes ? l : 0];
  const bool run = lanes == W && nd[W - 1] - nd[0] == W - 1;
  // (Doubles in two halves of H lanes, each a register wide.)
  D e[4][2], n[3][2];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
#pragma GCC unroll 4
    for (int h = 0; h < 2; ++h)
      e[k][h] = run ? load<D>(nv.eye[k] + nd[0] + h * H) : gather<D>(nv.eye[k], idx + h * H);
  alignas(32) float pc[4][W];
  if (nrm) {
#pragma GCC unroll 4
    for (int h = 0; h < 2; ++h) {
      D v[3];
      if (run) rows_xyz(nrm + 3 * (nd[0] + h * H), v);
      else gather_xyz(nrm, idx + h * H, v);
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) n[k][h] = v[k];
    }
    if (want_color)
      for (int l = 0; l < W; ++l) {
        const Vec4f c = src.color(nv.v0 + idx[l]);
        for (int k = 0; k < 4; ++k) pc[k][l] = c[k];
      }
  } else {
    alignas(32) double pn[3][W];
    for (std::size_t l = 0; l < lanes; ++l) {
      const std::size_t i = nd[l];
      if (lean) {
        const Vec3 nl = src.normal(nv.v0 + i);
        for (int k = 0; k < 3; ++k) pn[k][l] = nl[k];
        if (want_color) {
          const Vec4f c = src.color(nv.v0 + i);
          for (int k = 0; k < 4; ++k) pc[k][l] = c[k];
        }
      } else {
        // vertex_attrs: every other attribute, and the eye normal (transformed here already).
        auto&& v = src.vertex(nv.v0 + i);
        const Vec4 ev(nv.eye[0][i], nv.eye[1][i], nv.eye[2][i], nv.eye[3][i]);
        const Vec3 nl = vertex_attrs(s, v, ev, nmat, attrs + (q + l) * astride, needs);
        for (int k = 0; k < 3; ++k) pn[k][l] = nl[k];
        for (int k = 0; k < 4; ++k) pc[k][l] = v.color[k];
      }
    }
    for (std::size_t l = lanes; l < W; ++l) {  // the last group's unused lanes copy lane 0
      for (int k = 0; k < 3; ++k) pn[k][l] = pn[k][0];
      for (int k = 0; k < 4; ++k) pc[k][l] = pc[k][0];
    }
    for (int k = 0; k < 3; ++k)
      for (int h = 0; h < 2; ++h) n[k][h] = load<D>(pn[k] + h * H);
  }
  // As light_vertex: P = (eye / w) in double, then float (w = 1 in every lane, the usual affine
  // modelview: x / 1 = x exactly, the divisions are skipped).
  if (any(typename Lanes<V>::I((e[3][0] != 1.0) | (e[3][1] != 1.0))))
#pragma GCC unroll 4
    for (int k = 0; k < 3; ++k)
#pragma GCC unroll 4
      for (int h = 0; h < 2; ++h) e[k][h] = e[k][h] / e[3][h];
#pragma GCC unroll 4
  for (int k = 0; k < 3; ++k) P[k] = narrow(e[k]);
  if (lean)
#pragma GCC unroll 4
    for (int h = 0; h < 2; ++h) {
      D nh[3] = {n[0][h], n[1][h], n[2][h]};
      eye_normals(m, nh, normalize);
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) n[k][h] = nh[k];
    }
#pragma GCC unroll 4
  for (int k = 0; k < 3; ++k) N[k] = narrow(n[k]);
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    if (want_color) std::memcpy(&C[k], pc[k], sizeof(V));
    else C[k] = splat<V>(0);  // (not read)
}

// The lit colours (and, unless `lean`, vertex_attrs' other attributes) of the needed vertices,
// W = 4 or 16 (two groups of 8) at a time, into attrs (sets of `astride` floats): light_inputs,
// then the lighting.
template <class V, class Src>
[[gnu::always_inline]] inline void light_needed(const Context::State& s, const LightSetup& ls, const LightConsts<V>& lc,
                                                const Src& src, const Mat3& nmat, const NeededVerts& nv, bool lean,
                                                const AttrNeeds& needs, float* attrs, std::size_t astride) {
  constexpr int W = Lanes<V>::W;
  const bool two = s.two_side;
  const bool want_color = !lean || lc.side[0].cm || (two && lc.side[1].cm);
  double m[9];
  for (int k = 0; k < 9; ++k) m[k] = nmat(k % 3, k / 3);
  // The client's normals packed x y z, vertex by vertex from the chunk's first (no indices): read
  // there by vectors. Else null (normals come through src.normal).
  const double* nrm = nullptr;
  if constexpr (requires { src.indices, src.a.normals, src.first; })
    if (lean && !src.indices && src.a.normals) nrm = src.a.normals + (src.first + nv.v0) * 3;
  for (std::size_t q = 0; q < nv.n; q += W) {
    const std::size_t lanes = std::min<std::size_t>(W, nv.n - q);
    V P[3], N[3], C[4];
    if constexpr (IsX2<V>::value) {
      // Each group of eight on its own (in registers), then side by side.
      typedef decltype(V::a) T;
      constexpr std::size_t W1 = Lanes<T>::W;
      T p[2][3], n[2][3], c[2][4];
      light_inputs<T>(s, src, nmat, m, nrm, nv, q, std::min(lanes, W1), lean, want_color, needs, attrs, astride,
                      p[0], n[0], c[0]);
      if (lanes > W1)
        light_inputs<T>(s, src, nmat, m, nrm, nv, q + W1, lanes - W1, lean, want_color, needs, attrs, astride, p[1],
                        n[1], c[1]);
      else  // (the last group's second eight: copies, computed, not stored)
        for (int k = 0; k < 4; ++k) {
          if (k < 3) p[1][k] = p[0][k], n[1][k] = n[0][k];
          c[1][k] = c[0][k];
        }
      for (int k = 0; k < 3; ++k) P[k] = {p[0][k], p[1][k]}, N[k] = {n[0][k], n[1][k]};
      for (int k = 0; k < 4; ++k) C[k] = {c[0][k], c[1][k]};
    } else {
      light_inputs<V>(s, src, nmat, m, nrm, nv, q, lanes, lean, want_color, needs, attrs, astride, P, N, C);
    }
    V front[4], back[4];
    light_lanes(s, ls, lc, P, N, C, 0, front);
    float* const a = attrs + q * astride;
    store_rgba(front, a + kFront, astride, lanes);
    if (two) {
      const V nb[3] = {-N[0], -N[1], -N[2]};
      light_lanes(s, ls, lc, P, nb, C, 1, back);
    }
    if (astride > 4) store_rgba(two ? back : front, a + kBack, astride, lanes);
  }
}

template <class Src>
void light_needed_sse2(const Context::State& s, const LightSetup& ls, const LightConsts<F4>& lc, const Src& src,
                       const Mat3& nmat, const NeededVerts& nv, bool lean, const AttrNeeds& needs, float* attrs,
                       std::size_t astride) {
  light_needed<F4>(s, ls, lc, src, nmat, nv, lean, needs, attrs, astride);
}
#if defined(__x86_64__) && defined(__GNUC__)
template <class Src>
__attribute__((target("avx2"))) void light_needed_avx2(const Context::State& s, const LightSetup& ls,
                                                       const LightConsts<F16>& lc, const Src& src, const Mat3& nmat,
                                                       const NeededVerts& nv, bool lean, const AttrNeeds& needs,
                                                       float* attrs, std::size_t astride) {
  light_needed<F16>(s, ls, lc, src, nmat, nv, lean, needs, attrs, astride);
}
#endif

}  // namespace


// The vertex stage but the lit colours: eye-space normal, unlit colours (when not lit),
// texture coordinates (texgen, texture matrix), fog distance, eye position and normal into
// `a` (those in `need`). Returns the eye-space normal (unit if normalised) for lighting.
Vec3 vertex_attrs(const Context::State& s, const InVertex& v, const Vec4& eye, const Mat3& nmat, float* a,
                  const AttrNeeds& need) {
  Vec3 n = nmat * v.normal;
  if (s.on(Cap::Normalize) || s.shade == ShadeModel::Phong) {
    double len = n.norm();
    if (len > 0) n /= len;
  }
  if (!vertex_lighting(s)) {
    Vec4f c = clamp01(v.color);
    for (int k = 0; k < 4; ++k) a[kFront + k] = a[kBack + k] = c[k];
  }
  if (need.tex) {
    Vec4 tex = v.tex;
    for (int k = 0; k < 2; ++k) {
      if (!s.on(k == 0 ? Cap::TextureGenS : Cap::TextureGenT)) continue;
      switch (s.gen_mode[k]) {
        case TexGenMode::ObjectLinear: tex[k] = s.obj_plane[k].dot(v.position); break;
        case TexGenMode::EyeLinear: tex[k] = s.eye_plane[k].dot(eye); break;
        case TexGenMode::SphereMap: {
          Vec3 u = (eye.head<3>() / eye.w()).normalized();
          Vec3 nn = n.normalized();
          Vec3 r = u - 2 * nn.dot(u) * nn;
          double m = 2 * std::sqrt(r.x() * r.x() + r.y() * r.y() + (r.z() + 1) * (r.z() + 1));
          tex[k] = (k == 0 ? r.x() : r.y()) / m + 0.5;
          break;
        }
      }
    }
    if (s.on(Cap::Texture2D)) tex = s.top(MatrixMode::Texture) * tex;
    for (int k = 0; k < 4; ++k) a[kTex + k] = float(tex[k]);
  } else {
    for (int k = 0; k < 4; ++k) a[kTex + k] = 0;
  }
  a[kFog] = need.fog ? float(std::abs(eye.z())) : 0.0f;
  if (need.eye_normal) {
    for (int k = 0; k < 4; ++k) a[kEye + k] = float(eye[k]);
    for (int k = 0; k < 3; ++k) a[kNormal + k] = float(n[k]);
  } else {
    for (int k = kEye; k < kAttrs; ++k) a[k] = 0;
  }
  return n;
}

// Vertex stage: object coordinates to clip coordinates with all per-vertex attributes.
// `eye` and `clip` are the vertex's mv * position and proj * eye, computed by the caller.
PVert process_vertex(const Context::State& s, const LightSetup& ls, const InVertex& v, const Vec4& eye,
                     const Vec4& clip, const Mat3& nmat) {
  PVert out;
  out.clip = clip;
  const Vec3 n = vertex_attrs(s, v, eye, nmat, out.a);
  if (vertex_lighting(s)) {
    Vec4f f = light_vertex(s, ls, eye, n, v.color, 0);
    Vec4f b = s.two_side ? light_vertex(s, ls, eye, -n, v.color, 1) : f;
    for (int k = 0; k < 4; ++k) out.a[kFront + k] = f[k], out.a[kBack + k] = b[k];
  }
  return out;
}

DrawLights::DrawLights(const Context::State& s, const LightSetup& ls, [[maybe_unused]] bool avx2) {
  if (!vertex_lighting(s)) return;
#if defined(__x86_64__) && defined(__GNUC__)
  use_wide = avx2;
#endif
  if (use_wide) wide = std::make_unique<LightConsts<X2<F8>>>(s, ls);
  else narrow = std::make_unique<LightConsts<F4>>(s, ls);
}
DrawLights::~DrawLights() = default;

template <class Src>
void light_needed_vertices(const DrawLights& dl, const Context::State& s, const LightSetup& ls, const Src& src,
                           const Mat3& nmat, const NeededVerts& nv, bool lean, const AttrNeeds& needs, float* attrs,
                           std::size_t astride) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (dl.use_wide) return light_needed_avx2(s, ls, *dl.wide, src, nmat, nv, lean, needs, attrs, astride);
#endif
  light_needed_sse2(s, ls, *dl.narrow, src, nmat, nv, lean, needs, attrs, astride);
}
template void light_needed_vertices<InSource>(const DrawLights&, const Context::State&, const LightSetup&,
                                              const InSource&, const Mat3&, const NeededVerts&, bool,
                                              const AttrNeeds&, float*, std::size_t);
template void light_needed_vertices<ArraySource>(const DrawLights&, const Context::State&, const LightSetup&,
                                                 const ArraySource&, const Mat3&, const NeededVerts&, bool,
                                                 const AttrNeeds&, float*, std::size_t);

Vec4f Raster::phong_color(const float* a, int side) const {
  Vec4 eye(a[kEye], a[kEye + 1], a[kEye + 2], a[kEye + 3]);
  Vec3 n(a[kNormal], a[kNormal + 1], a[kNormal + 2]);
  double len = n.norm();
  if (len > 0) n /= len;
  Vec4f vc(a[kFront], a[kFront + 1], a[kFront + 2], a[kFront + 3]);
  return light_vertex(s, lights, eye, side ? Vec3(-n) : n, vc, side);
}

}  // namespace wedge::render::raster

namespace wedge::render {
using namespace raster;

namespace {
void pow_lanes4(const float* x, std::size_t n, float y, float* out) {
  for (std::size_t i = 0; i < n; i += 4) {
    F4 v = bcast(1), r;
    std::memcpy(&v, x + i, sizeof(float) * std::min<std::size_t>(4, n - i));
    r = vpow(v, y);
    std::memcpy(out + i, &r, sizeof(float) * std::min<std::size_t>(4, n - i));
  }
}
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void pow_lanes8(const float* x, std::size_t n, float y, float* out) {
  for (std::size_t i = 0; i < n; i += 8) {
    F8 v = splat<F8>(1), r;
    std::memcpy(&v, x + i, sizeof(float) * std::min<std::size_t>(8, n - i));
    r = vpow(v, y);
    std::memcpy(out + i, &r, sizeof(float) * std::min<std::size_t>(8, n - i));
  }
}
#endif
}  // namespace

void lighting_pow(const float* x, std::size_t n, float y, float* out, bool avx2) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (avx2 && cpu_has_avx2()) return pow_lanes8(x, n, y, out);
#endif
  (void)avx2;
  pow_lanes4(x, n, y, out);
}
float lighting_pow(float x, float y) { return gl_pow(x, y); }

void lighting_normals(const Mat3& nmat, const double* n, std::size_t count, bool normalize, double* out) {
  double m[9];
  for (int k = 0; k < 9; ++k) m[k] = nmat(k % 3, k / 3);
  for (std::size_t i = 0; i < count; i += 2) {
    Lanes<F4>::D v[3];  // the SSE2 build's (the AVX2 one's: the same operations on four lanes)
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 2; ++l) v[k][l] = i + l < count ? n[3 * (i + l) + k] : 1.0;
    eye_normals(m, v, normalize);
    for (std::size_t l = 0; l < 2 && i + l < count; ++l)
      for (int k = 0; k < 3; ++k) out[3 * (i + l) + k] = v[k][l];
  }
}

}  // namespace wedge::render
