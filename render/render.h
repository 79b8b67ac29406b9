// wedge::render — the OpenGL-1.x-style software rasterizer. It knows only kernel/ (the Mesh).
// Its enumerations carry OpenGL's names, so state reads as it would in GL.
#pragma once
#include "kernel/kernel.h"

namespace wedge::render {

enum class Primitive { Points, Lines, LineStrip, LineLoop, Triangles, TriangleStrip, TriangleFan, Quads, QuadStrip, Polygon };
enum class DepthFunc { Never, Less, Equal, LessEqual, Greater, NotEqual, GreaterEqual, Always };
enum class ShadeModel { Flat, Smooth, Phong };

}  // namespace wedge::render
