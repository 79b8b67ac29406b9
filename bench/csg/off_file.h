// Operands as OFF files with %.17g, written and read as they are: no welding, no mending, no
// checks, so that an invalid operand comes back as it went out (tessellate's write_mesh and
// read_mesh would mend or refuse it). The fuzzer saves its cases so (a folder: the operands'
// .off files in name order, the op in op.txt); its replay and the stage bench (bench_stages
// dir:PATH) read them. All throw std::runtime_error naming the file.
#pragma once

#include <string>
#include <vector>

#include "csg/boolean.h"

#include "kernel/mesh.h"

namespace wedge::fuzz {

void write_off(const std::string& path, const Mesh& m);
Mesh read_off(const std::string& path);
// The op a word names (boolean_op_name's words).
BooleanOp parse_op(const std::string& word);
// A saved case's op (DIR/op.txt) and operands (DIR's .off files in name order; at least one).
BooleanOp read_case_op(const std::string& dir);
std::vector<Mesh> read_case_operands(const std::string& dir);

}  // namespace wedge::fuzz
