// Operands as OFF files with %.17g, written and read as they are: no welding, no mending, no
// checks, so that an invalid operand comes back as it went out (tessellate's write_mesh and
// read_mesh would mend or refuse it). The fuzzer saves its cases so; the stage bench reads them
// (bench_stages dir:PATH). Both throw std::runtime_error naming the file.
#pragma once

#include <string>

#include "kernel/mesh.h"

namespace wedge::fuzz {

void write_off(const std::string& path, const Mesh& m);
Mesh read_off(const std::string& path);

}  // namespace wedge::fuzz
