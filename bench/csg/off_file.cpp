// OFF files as the fuzzer and the stage bench read and write them (off_file.h).
#include "bench/csg/off_file.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace wedge::fuzz {

namespace {

[[noreturn]] void fail_errno(const std::string& what, const std::string& path) {
  throw std::runtime_error(what + " '" + path + "': " + std::strerror(errno));
}

}  // namespace

void write_off(const std::string& path, const Mesh& m) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) fail_errno("cannot open", path);
  std::fprintf(f, "OFF\n%zu %zu 0\n", m.positions.size(), m.triangles.size());
  for (const auto& p : m.positions) std::fprintf(f, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  for (const auto& t : m.triangles) std::fprintf(f, "3 %u %u %u\n", t[0], t[1], t[2]);
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad) fail_errno("cannot write", path);
}

Mesh read_off(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open '" + path + "'");
  const auto bad = [&](const std::string& what) { throw std::runtime_error(path + ": " + what); };
  std::string head;
  std::size_t nv = 0, nf = 0, ne = 0;
  if (!(in >> head >> nv >> nf >> ne) || head != "OFF") bad("not 'OFF' and the counts");
  Mesh m;
  for (std::size_t i = 0; i < nv; ++i) {
    std::string s[3];  // strtod reads the "nan" and "inf" that write_off writes for a bad operand; >> does not
    if (!(in >> s[0] >> s[1] >> s[2])) bad("vertex " + std::to_string(i) + " missing");
    double x[3];
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      x[k] = std::strtod(s[k].c_str(), &end);
      if (*end != '\0') bad("vertex " + std::to_string(i) + ": '" + s[k] + "' is not a number");
    }
    m.positions.emplace_back(x[0], x[1], x[2]);
  }
  for (std::size_t i = 0; i < nf; ++i) {
    int n = 0;
    Mesh::Triangle t;
    if (!(in >> n >> t[0] >> t[1] >> t[2]) || n != 3) bad("face " + std::to_string(i) + " is not '3 a b c'");
    m.triangles.push_back(t);
  }
  return m;
}

BooleanOp parse_op(const std::string& word) {
  for (BooleanOp op : {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference})
    if (word == boolean_op_name(op)) return op;
  throw std::runtime_error("unknown op '" + word + "' (union, intersection or difference)");
}

BooleanOp read_case_op(const std::string& dir) {
  std::string word;
  if (!(std::ifstream(dir + "/op.txt") >> word)) throw std::runtime_error("cannot read '" + dir + "/op.txt'");
  return parse_op(word);
}

std::vector<Mesh> read_case_operands(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".off") files.push_back(e.path().string());
  if (files.empty()) throw std::runtime_error(dir + " holds no operand .off files");
  std::sort(files.begin(), files.end());
  std::vector<Mesh> ms;
  for (const auto& f : files) ms.push_back(read_off(f));
  return ms;
}

}  // namespace wedge::fuzz
