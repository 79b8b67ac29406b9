// Issue 11's boolean benchmark: wedge's engine against CGAL's corefinement (Epick and Epeck,
// in-process) and Manifold (manifold-3d's WASM build under Node), on the same operands in the
// same run.
//
// Each (case, engine, thread count) runs in a process of its own, so its peak memory (ru_maxrss)
// is its own: the driver (no arguments, or filters) starts `bench_boolean --one ...` per row and
// prints a table. A row's time is the median of --repeats runs of the whole case (operands in,
// result mesh out, as each engine's API takes and gives them); a run longer than 20 s is not
// repeated. Each run starts after the previous run's result is released, for every engine: kept,
// it held memory the next run then took fresh from the kernel (a 1M-sphere result is 36 MB, some
// 9,000 pages at about 11 us a fault on the benchmark's VM), which no caller pays who keeps one
// result. The first run of a process still pays for all its memory fresh. Validity is judged after timing, on the output as doubles: closed, 2-manifold and
// outward (tests/support: closed_manifold_outward) and free of self-intersections by CGAL's exact
// test (exact_self_intersects). Volume is the exact volume of those doubles.
//
//   bench_boolean [--cases a,b] [--engines wedge,cgal-epick,cgal-epeck,manifold] [--threads 1,2]
//                 [--repeats 5] [--timeout 600] [--quick]
//
// --cases keeps the cases whose names contain one of the words; --quick leaves out the 1M spheres.
// CGAL's corefinement and Manifold's WASM build are serial: they run once, at "1" thread.
#include <oneapi/tbb/global_control.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/csg/recipe.h"
#include "csg/boolean.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"
#include "kernel/memory.h"

using namespace wedge;
using namespace wedge::bench;
using namespace wedge::testing;

namespace {

struct Case {
  std::string name;
  std::function<std::vector<Mesh>()> operands;
  Recipe recipe;
  int sphere_size = 0;  // the sphere series (for the slope), else 0
};

Step all_of(BooleanOp op, int n) {
  Step s{op, {}};
  for (int i = 0; i < n; ++i) s.inputs.push_back(i);
  return s;
}

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  const BooleanOp ops[] = {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference};
  for (int n : {4096, 65536, 1048576}) {
    const std::string size = n == 4096 ? "4k" : n == 65536 ? "65k" : "1M";
    for (BooleanOp op : ops)
      cases.push_back({"spheres " + size + " " + boolean_op_name(op), [n] { return overlapping_spheres(n); },
                       {{op, {0, 1}}}, n});
  }
  cases.push_back({"classic figure", [] { return classic_figure_operands(16384, 128); },
                   {{BooleanOp::Intersection, {0, 1}}, {BooleanOp::Difference, {-1, 2, 3, 4}}}});
  cases.push_back({"lattice 512 spheres union", [] { return sphere_lattice(8, 1280); }, {all_of(BooleanOp::Union, 512)}});
  cases.push_back({"plate minus 400 cylinders", [] { return plate_and_cylinders(20, 32); },
                   {all_of(BooleanOp::Difference, 401)}});
  cases.push_back({"octet truss 3x3x3 nodes union", [] { return octet_truss(2, 0.08, 32, 320); },
                   {all_of(BooleanOp::Union, static_cast<int>(octet_truss(2, 0.08, 32, 320).size()))}});
  cases.push_back({"menger sponge level 3", [] { return menger_operands(3); },
                   {all_of(BooleanOp::Difference, static_cast<int>(menger_operands(3).size()))}});
  for (const BooleanCase& c : degenerate_cases())
    for (BooleanOp op : ops) {
      const std::string name = c.name;
      cases.push_back({"degenerate: " + c.name + " " + boolean_op_name(op), [name] { return degenerate_case(name).operands; },
                       {{op, {0, 1}}}});
    }
  return cases;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

long maxrss_kb_self() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

PeerRun wedge_recipe(const std::vector<Mesh>& operands, const Recipe& recipe) {
  PeerRun r;
  try {
    Mesh previous;
    for (const Step& s : recipe) {
      std::vector<const Mesh*> in;
      for (int i : s.inputs) in.push_back(i < 0 ? &previous : &operands.at(i));
      BooleanResult out = boolean(s.op, in);
      previous = std::move(out.mesh);
    }
    r.mesh = std::move(previous);
    r.ok = true;
  } catch (const std::exception& e) {
    r.why = e.what();
  }
  return r;
}

// --- Manifold through Node ---
void write_mesh(const std::string& file, const Mesh& m) {
  std::ofstream out(file, std::ios::binary);
  const std::uint32_t nv = static_cast<std::uint32_t>(m.positions.size()), nt = static_cast<std::uint32_t>(m.triangles.size());
  out.write(reinterpret_cast<const char*>(&nv), 4);
  out.write(reinterpret_cast<const char*>(&nt), 4);
  for (const auto& p : m.positions) out.write(reinterpret_cast<const char*>(p.data()), 24);
  for (const auto& t : m.triangles) out.write(reinterpret_cast<const char*>(t.data()), 12);
  if (!out) throw std::runtime_error("cannot write " + file);
}

Mesh read_mesh(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::uint32_t nv = 0, nt = 0;
  in.read(reinterpret_cast<char*>(&nv), 4);
  in.read(reinterpret_cast<char*>(&nt), 4);
  Mesh m;
  m.positions.resize(nv);
  m.triangles.resize(nt);
  for (auto& p : m.positions) in.read(reinterpret_cast<char*>(p.data()), 24);
  for (auto& t : m.triangles) in.read(reinterpret_cast<char*>(t.data()), 12);
  if (!in) throw std::runtime_error("cannot read " + file);
  return m;
}

std::string json_field(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return "";
  std::size_t b = at + key.size() + 3, e = b;
  if (json[b] == '"') {
    e = json.find('"', b + 1);
    return json.substr(b + 1, e - b - 1);
  }
  while (e < json.size() && json[e] != ',' && json[e] != '}') ++e;
  return json.substr(b, e - b);
}

struct Row {
  double ms = NAN;
  int runs = 0;
  std::size_t triangles = 0;
  double volume = NAN;
  std::string valid, error;
  long maxrss_kb = 0;
};

Row run_manifold(const std::vector<Mesh>& operands, const Recipe& recipe, int repeats) {
  Row row;
  const std::string script = std::string(WEDGE_BENCH_CSG_DIR) + "/manifold/run.mjs";
  if (!std::filesystem::exists(std::string(WEDGE_BENCH_CSG_DIR) + "/manifold/node_modules/manifold-3d")) {
    row.error = "manifold-3d not installed (cd bench/csg/manifold && npm ci)";
    return row;
  }
  char tmpl[] = "/tmp/wedge_bench_boolean_XXXXXX";
  if (!mkdtemp(tmpl)) {
    row.error = "mkdtemp failed";
    return row;
  }
  const std::string dir = tmpl;
  for (std::size_t k = 0; k < operands.size(); ++k) write_mesh(dir + "/op" + std::to_string(k) + ".bin", operands[k]);
  {
    std::ofstream j(dir + "/recipe.json");
    j << "{\"operands\": " << operands.size() << ", \"steps\": [";
    for (std::size_t s = 0; s < recipe.size(); ++s) {
      j << (s ? ", " : "") << "{\"op\": \"" << boolean_op_name(recipe[s].op) << "\", \"inputs\": [";
      for (std::size_t i = 0; i < recipe[s].inputs.size(); ++i) j << (i ? ", " : "") << recipe[s].inputs[i];
      j << "]}";
    }
    j << "]}\n";
  }
  int pipefd[2];
  if (pipe(pipefd) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(pipefd[1], 1);
    close(pipefd[0]);
    const std::string reps = std::to_string(repeats);
    execlp("node", "node", script.c_str(), dir.c_str(), reps.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(pipefd[1]);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = read(pipefd[0], buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  close(pipefd[0]);
  int status = 0;
  rusage u{};
  wait4(pid, &status, 0, &u);
  row.maxrss_kb = u.ru_maxrss;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || json_field(out, "ms").empty()) {
    row.error = "node failed (exit " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")";
  } else {
    row.ms = std::stod(json_field(out, "ms"));
    row.runs = std::stoi(json_field(out, "runs"));
    const std::string st = json_field(out, "status");
    if (st != "0" && st != "NoError") row.error = "Manifold status " + st;
    const Mesh m = read_mesh(dir + "/out.bin");
    row.triangles = m.triangle_count();
    row.volume = exact_volume(m);
    std::string where;
    row.valid = closed_manifold_outward(m);
    if (row.valid.empty() && exact_self_intersects(m, &where)) row.valid = "self-intersecting: " + where;
    if (row.valid.empty()) row.valid = "valid";
  }
  std::filesystem::remove_all(dir);
  return row;
}

// One row in this process; prints it as a tab-separated RESULT line.
int run_one(const std::string& case_name, const std::string& engine, int threads, int repeats) {
  const auto cases = all_cases();
  const auto it = std::find_if(cases.begin(), cases.end(), [&](const Case& c) { return c.name == case_name; });
  if (it == cases.end()) {
    std::cerr << "bench_boolean: no case named '" << case_name << "'\n";
    return 2;
  }
  const std::vector<Mesh> operands = it->operands();
  Row row;
  if (engine == "manifold") {
    row = run_manifold(operands, it->recipe, repeats);
  } else {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    std::function<PeerRun()> go;
    if (engine == "wedge") go = [&] { return wedge_recipe(operands, it->recipe); };
    else if (engine == "cgal-epick") go = [&] { return cgal_recipe(CgalKernel::Epick, operands, it->recipe); };
    else if (engine == "cgal-epeck") go = [&] { return cgal_recipe(CgalKernel::Epeck, operands, it->recipe); };
    else {
      std::cerr << "bench_boolean: unknown engine '" << engine << "'\n";
      return 2;
    }
    std::vector<double> times;
    PeerRun last;
    for (int r = 0; r < repeats; ++r) {
      last = PeerRun{};  // (the previous result released first: see the top)
      const auto t0 = std::chrono::steady_clock::now();
      last = go();
      times.push_back(ms_since(t0));
      if (!last.ok || times.front() > 20000) break;
    }
    row.maxrss_kb = maxrss_kb_self();  // before the checks below, which are not the engine's
    row.runs = static_cast<int>(times.size());
    if (!last.ok) {
      row.error = last.why;
    } else {
      row.ms = median(times);
      row.triangles = last.mesh.triangle_count();
      row.volume = exact_volume(last.mesh);
      std::string where;
      row.valid = closed_manifold_outward(last.mesh);
      if (row.valid.empty() && exact_self_intersects(last.mesh, &where)) row.valid = "self-intersecting: " + where;
      if (row.valid.empty()) row.valid = "valid";
    }
  }
  auto clean = [](std::string s) {
    std::replace(s.begin(), s.end(), '\t', ' ');
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '|', '/');
    return s;
  };
  std::printf("RESULT\t%.3f\t%d\t%zu\t%.17g\t%s\t%ld\t%s\n", row.ms, row.runs, row.triangles, row.volume,
              clean(row.valid).c_str(), row.maxrss_kb, clean(row.error).c_str());
  return 0;
}

// Runs `self --one ...` with a time limit; the child's RESULT line, or a row saying what happened.
Row spawn_one(const std::string& self, const std::string& case_name, const std::string& engine, int threads,
              int repeats, int timeout_s) {
  Row row;
  int pipefd[2];
  if (pipe(pipefd) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);  // its own group, so a timeout also ends its Node child
    dup2(pipefd[1], 1);
    close(pipefd[0]);
    const std::string t = std::to_string(threads), r = std::to_string(repeats);
    execl(self.c_str(), self.c_str(), "--one", case_name.c_str(), engine.c_str(), t.c_str(), r.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid, pid);
  close(pipefd[1]);
  std::string out;
  const auto t0 = std::chrono::steady_clock::now();
  bool timed_out = false;
  int status = 0;
  rusage u{};
  for (;;) {
    fd_set fds;
    FD_ZERO(&fds);
    FD_SET(pipefd[0], &fds);
    timeval tv{0, 200000};
    if (select(pipefd[0] + 1, &fds, nullptr, nullptr, &tv) > 0) {
      char buf[4096];
      const ssize_t n = read(pipefd[0], buf, sizeof buf);
      if (n > 0) out.append(buf, static_cast<std::size_t>(n));
      if (n == 0) break;
    }
    if (ms_since(t0) > 1000.0 * timeout_s) {
      timed_out = true;
      kill(-pid, SIGKILL);
      break;
    }
  }
  close(pipefd[0]);
  wait4(pid, &status, 0, &u);
  if (timed_out) {
    row.error = "timeout (> " + std::to_string(timeout_s) + " s)";
    return row;
  }
  const auto at = out.find("RESULT\t");
  if (at == std::string::npos) {
    row.error = WIFSIGNALED(status) ? "crashed (signal " + std::to_string(WTERMSIG(status)) + ")" : "no result";
    return row;
  }
  std::istringstream line(out.substr(at + 7));
  std::string f[6];  // ms, runs, triangles, volume, valid, maxrss; the error is the rest of the line
  for (auto& s : f) std::getline(line, s, '\t');
  std::getline(line, row.error);
  row.ms = std::stod(f[0]);
  row.runs = std::stoi(f[1]);
  row.triangles = std::stoull(f[2]);
  row.volume = std::stod(f[3]);
  row.valid = f[4];
  row.maxrss_kb = std::stol(f[5]);
  return row;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string x; std::getline(in, x, ',');)
    if (!x.empty()) out.push_back(x);
  return out;
}

std::string fmt(const char* f, double x) {
  if (std::isnan(x)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  wedge::tune_malloc(argv);  // first: it may execute the program again
  if (argc == 6 && std::string(argv[1]) == "--one") return run_one(argv[2], argv[3], std::atoi(argv[4]), std::atoi(argv[5]));

  std::vector<std::string> filters, engines = {"wedge", "cgal-epick", "cgal-epeck", "manifold"};
  std::vector<int> thread_counts = {1, 2};
  int repeats = 5, timeout_s = 600;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "bench_boolean: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--cases") filters = split(next());
    else if (a == "--engines") engines = split(next());
    else if (a == "--threads") {
      thread_counts.clear();
      for (const auto& t : split(next())) thread_counts.push_back(std::stoi(t));
    } else if (a == "--repeats") repeats = std::stoi(next());
    else if (a == "--timeout") timeout_s = std::stoi(next());
    else if (a == "--quick") quick = true;
    else {
      std::cerr << "bench_boolean: unknown argument '" << a << "' (see the comment at the top of bench_boolean.cpp)\n";
      return 2;
    }
  }
  const std::string self = std::filesystem::canonical("/proc/self/exe");

  std::printf("| case | engine | threads | ms | / wedge 1t | / wedge 2t | triangles | volume | valid | peak MB |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);
  // For the slopes: (engine, threads, op) -> (size, ms) over the sphere series.
  std::map<std::string, std::vector<std::pair<double, double>>> series;
  for (const Case& c : all_cases()) {
    if (quick && c.sphere_size > 100000) continue;
    if (!filters.empty() && std::none_of(filters.begin(), filters.end(),
                                         [&](const std::string& f) { return c.name.find(f) != std::string::npos; }))
      continue;
    std::map<int, double> wedge_ms;
    std::vector<std::tuple<std::string, int, Row>> rows;
    for (const std::string& e : engines) {
      const bool serial = e != "wedge";
      for (int t : thread_counts) {
        if (serial && t != thread_counts.front()) continue;
        Row row = spawn_one(self, c.name, e, serial ? 1 : t, repeats, timeout_s);
        if (e == "wedge") wedge_ms[t] = row.ms;
        if (c.sphere_size && !std::isnan(row.ms)) {
          const std::string op = c.name.substr(c.name.rfind(' ') + 1);
          series[e + "\t" + std::to_string(serial ? 1 : t) + "\t" + op].push_back({double(c.sphere_size), row.ms});
        }
        rows.emplace_back(e, serial ? 1 : t, row);
      }
    }
    for (const auto& [e, t, row] : rows) {
      auto ratio = [&](int wt) {
        auto w = wedge_ms.find(wt);
        return (w == wedge_ms.end() || std::isnan(row.ms)) ? std::string("-") : fmt("%.2fx", row.ms / w->second);
      };
      const std::string status = row.error.empty() ? row.valid : (row.valid.empty() ? row.error : row.valid + "; " + row.error);
      std::printf("| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s |\n", c.name.c_str(), e.c_str(), t,
                  fmt("%.1f", row.ms).c_str(), ratio(1).c_str(), ratio(2).c_str(),
                  row.triangles ? std::to_string(row.triangles).c_str() : "-", fmt("%.12g", row.volume).c_str(),
                  status.c_str(), row.maxrss_kb ? fmt("%.0f", row.maxrss_kb / 1024.0).c_str() : "-");
      std::fflush(stdout);
    }
  }
  // Log-log slope of time against triangles per sphere over the three sizes (least squares).
  if (!series.empty()) {
    std::printf("\n| engine | threads | op | log-log slope (ms vs triangles per sphere) |\n|---|---|---|---|\n");
    for (const auto& [key, pts] : series) {
      if (pts.size() < 2) continue;
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (const auto& [x, y] : pts) {
        sx += std::log(x), sy += std::log(y), sxx += std::log(x) * std::log(x), sxy += std::log(x) * std::log(y);
      }
      const double n = double(pts.size()), slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
      std::string k;
      for (char ch : key) k += ch == '\t' ? std::string(" | ") : std::string(1, ch);
      std::printf("| %s | %.2f (%zu sizes) |\n", k.c_str(), slope, pts.size());
    }
  }
  return 0;
}
