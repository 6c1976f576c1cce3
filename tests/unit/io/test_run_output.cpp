// What a run writes: the VTU encodings (zlib blocks decompress to the exact
// values; both encodings hold the same arrays), summary.json (valid JSON
// whatever the case name, paths and command line hold), and the contact fields
// (contact_pressure is the pressure a uniformly pressed face feels).
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "io/run_output.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/generators.hpp"
#include "problem/contact_rows.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

namespace vpc {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::uint64_t u64(const std::string& s, std::size_t at) {
  std::uint64_t v;
  std::memcpy(&v, s.data() + at, sizeof v);
  return v;
}

/// The bytes of every DataArray of a VTU file (Points' array under "Points"),
/// decoded from the appended data as VTK reads it: raw (UInt64 byte count) or
/// zlib (UInt64 header [blocks, block size, last block size, compressed sizes]).
std::map<std::string, std::string> read_vtu_arrays(const fs::path& path) {
  const std::string f = read_all(path);
  const std::size_t data = f.find('_', f.find("<AppendedData encoding=\"raw\">")) + 1;
  EXPECT_NE(data, std::string::npos);
  const std::string xml = f.substr(0, data);
  EXPECT_NE(xml.find("header_type=\"UInt64\""), std::string::npos);
  const bool zlib = xml.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos;
  std::map<std::string, std::string> arrays;
  const std::regex array_re("<DataArray ([^>]*)offset=\"([0-9]+)\"");
  const std::regex name_re("Name=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), array_re); it != std::sregex_iterator(); ++it) {
    std::smatch name;
    const std::string attrs = (*it)[1];
    const std::string key = std::regex_search(attrs, name, name_re) ? std::string(name[1]) : "Points";
    std::size_t at = data + std::stoull((*it)[2]);
    std::string bytes;
    if (!zlib) {
      bytes = f.substr(at + 8, u64(f, at));
    } else {
      const std::uint64_t nb = u64(f, at), block = u64(f, at + 8), last = u64(f, at + 16);
      std::size_t z = at + 8 * (3 + nb);
      for (std::uint64_t b = 0; b < nb; ++b) {
        const std::uint64_t zsize = u64(f, at + 8 * (3 + b));
        uLongf n = b + 1 < nb ? block : last;
        std::string out(n, '\0');
        EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(f.data() + z),
                             zsize),
                  Z_OK);
        EXPECT_EQ(n, b + 1 < nb ? block : last);
        bytes += out;
        z += zsize;
      }
    }
    arrays[key] = bytes;
  }
  return arrays;
}

std::vector<double> doubles(const std::string& bytes) {
  std::vector<double> v(bytes.size() / sizeof(double));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(double));
  return v;
}

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("vpc_test_run_output_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(VtuWriter, ZlibBlocksHaveVtkHeaderAndDecompressExactly) {
  std::vector<double> v(1000);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(0.1 * static_cast<double>(i)) * 1e3 + 1e-12 * i;
  const VtuEncoding e{VtuCompression::zlib, 3000, 6};
  const std::vector<char> block = encode_vtu_block(v.data(), v.size() * sizeof(double), e);
  std::string s(block.begin(), block.end());
  // 8000 bytes in blocks of 3000: 3 blocks, the last of 2000 bytes.
  ASSERT_EQ(u64(s, 0), 3u);
  EXPECT_EQ(u64(s, 8), 3000u);
  EXPECT_EQ(u64(s, 16), 2000u);
  std::size_t z = 8 * 6, total = 0;
  std::string out;
  for (int b = 0; b < 3; ++b) {
    const std::uint64_t zsize = u64(s, 8 * (3 + b));
    uLongf n = 3000;
    std::string part(n, '\0');
    ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(part.data()), &n, reinterpret_cast<const Bytef*>(s.data() + z), zsize),
              Z_OK);
    out += part.substr(0, n);
    z += zsize;
    total += zsize;
  }
  EXPECT_EQ(s.size(), 8 * 6 + total);
  EXPECT_EQ(doubles(out), v);

  // Raw: a UInt64 byte count and the bytes.
  const std::vector<char> raw = encode_vtu_block(v.data(), v.size() * sizeof(double), {VtuCompression::none});
  ASSERT_EQ(raw.size(), 8 + 8000u);
  EXPECT_EQ(u64(std::string(raw.begin(), raw.end()), 0), 8000u);
  EXPECT_EQ(std::memcmp(raw.data() + 8, v.data(), 8000), 0);
}

TEST(VtuWriter, BothEncodingsWriteTheSameArrays) {
  const Mesh mesh = make_rectangle({0, 0, 0}, {2, 1, 0}, 6, 3);
  VtuField u{"displacement", 3, {}}, s{"von_mises", 1, {}};
  for (int i = 0; i < mesh.n_nodes() * 3; ++i) u.values.push_back(0.001 * i * i - 0.5);
  for (int c = 0; c < mesh.n_cells(); ++c) s.values.push_back(1.0 / (c + 1));
  const fs::path dir = temp_dir("encodings");
  write_vtu(dir / "raw.vtu", mesh, {u}, {s}, {VtuCompression::none});
  write_vtu(dir / "zlib.vtu", mesh, {u}, {s}, {VtuCompression::zlib, 100, 1});  // many blocks, a partial last one
  const auto raw = read_vtu_arrays(dir / "raw.vtu"), zlib = read_vtu_arrays(dir / "zlib.vtu");
  EXPECT_EQ(read_all(dir / "zlib.vtu").find("compressor"), read_all(dir / "zlib.vtu").find("compressor=\"vtkZLib"));
  EXPECT_EQ(read_all(dir / "raw.vtu").find("compressor"), std::string::npos);
  ASSERT_EQ(raw.size(), 6u);  // displacement, von_mises, Points, connectivity, offsets, types
  EXPECT_EQ(raw, zlib);
  EXPECT_EQ(doubles(zlib.at("displacement")), u.values);
  EXPECT_EQ(doubles(zlib.at("von_mises")), s.values);
}

TEST(VtuWriter, CompressionNames) {
  EXPECT_EQ(vtu_compression("zlib"), VtuCompression::zlib);
  EXPECT_EQ(vtu_compression("none"), VtuCompression::none);
  EXPECT_THROW(vtu_compression("gzip"), Error);
}

// A block on a flat foundation, clamped on top and pressed down by its weight q
// per unit volume; ν = 0, so the exact solution is one-dimensional (u_x = 0,
// σ_yy(y) = q (y − H/2)) and the foundation carries half the weight as the
// uniform pressure q H / 2 on the whole bottom face.
std::string pressed_block(const std::string& name, const std::string& output) {
  return R"([case]
name = )" + name + R"(
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [8, 4]
[boundary]
clamped = ["top"]
contact = ["bottom"]
[elasticity]
kind = "plane-stress"
E = 100.0
nu = 0.0
[loads]
f0 = ["0", "-3"]
[contact]
gap = 0.0
[time]
T = 1.0
steps = 2
[output]
every = 1
probes = [[1.0, 0.5]]
)" + output;
}

struct Ran {
  Case c;
  fs::path dir;
};

Ran run_case(const std::string& text, const fs::path& dir, const std::vector<std::string>& argv = {}) {
  Ran r{parse_case(text, "test.toml", "."), dir};
  r.c.output.directory = dir;
  r.c.output.command_line = argv;
  TimeStepper stepper(r.c.problem, r.c.solvers);
  RunOutput out(stepper, r.c.output);
  out.start();
  while (!stepper.done()) out.record(stepper.step());
  out.finish(1.0);
  return r;
}

TEST(RunOutput, ContactPressureOfAUniformlyPressedFace) {
  const fs::path dir = temp_dir("pressure");
  run_case(pressed_block("\"block\"", ""), dir);
  const auto a = read_vtu_arrays(dir / "solution_00002.vtu");
  const auto x = doubles(a.at("Points")), p = doubles(a.at("contact_pressure")), f = doubles(a.at("contact_force"));
  const double q = 3, H = 1, W = 2;
  double total = 0;
  int interior = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double xi = x[3 * i], yi = x[3 * i + 1];
    total += f[3 * i + 1];  // the foundation pushes up: −λ ν with ν = (0, −1)
    if (yi > 1e-12) {
      EXPECT_EQ(p[i], 0.0) << "off Γ3 at node " << i;
    } else if (xi > 1e-12 && xi < W - 1e-12) {
      EXPECT_NEAR(p[i], q * H / 2, 1e-9) << "at x = " << xi;
      ++interior;
    }
  }
  EXPECT_EQ(interior, 7);
  EXPECT_NEAR(total, q * H * W / 2, 1e-9);
  EXPECT_EQ(a.count("beta"), 1u);
  EXPECT_EQ(a.count("damage"), 0u);
}

// Issue 26 item 21: the cell field `material` (an index into summary.json's
// materials) is an integer field, Int32, not Float64.
TEST(RunOutput, MaterialFieldIsInt32) {
  const fs::path dir = temp_dir("material_int32");
  run_case(pressed_block("\"block\"", R"([[material]]
name = "right"
where = "x > 1"
[material.elasticity]
E = 200.0
nu = 0.0
)"),
           dir);
  const std::string xml = read_all(dir / "solution_00002.vtu");
  EXPECT_NE(xml.find("<DataArray type=\"Int32\" Name=\"material\""), std::string::npos);
  const std::string bytes = read_vtu_arrays(dir / "solution_00002.vtu").at("material");
  std::vector<std::int32_t> m(bytes.size() / sizeof(std::int32_t));
  ASSERT_EQ(m.size(), 64u);  // 8 x 4 squares, 2 triangles each
  std::memcpy(m.data(), bytes.data(), bytes.size());
  EXPECT_EQ(std::count(m.begin(), m.end(), 0), 32);  // x < 1: the body's material
  EXPECT_EQ(std::count(m.begin(), m.end(), 1), 32);  // x > 1: "right"
}

std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

TEST(RunOutput, OneProcessWritesOneVtuPerOutputStepWithoutRanks) {
  // What a one-process run has always written: no pieces, no .pvtu, no "rank"
  // field, no "engine" in summary.json.
  const fs::path dir = temp_dir("one_process");
  run_case(pressed_block("\"block\"", ""), dir);
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"history.csv", "probes.csv", "summary.json", "solution.pvd",
                                                  "solution_00000.vtu", "solution_00001.vtu", "solution_00002.vtu"}));
  const auto a = read_vtu_arrays(dir / "solution_00002.vtu");
  EXPECT_EQ(a.count("rank"), 0u);
  EXPECT_EQ(a.count("stress"), 1u);
  const std::string pvd = read_all(dir / "solution.pvd");
  EXPECT_NE(pvd.find("file=\"solution_00002.vtu\""), std::string::npos) << pvd;
  EXPECT_EQ(pvd.find("pvtu"), std::string::npos) << pvd;
  EXPECT_FALSE(nlohmann::json::parse(read_all(dir / "summary.json")).contains("ranks"));
  // The probe's row: u, σ (11, 22, 12), von Mises and β at (1, 0.5), every step.
  std::ifstream probes(dir / "probes.csv");
  std::string header, row;
  std::getline(probes, header);
  EXPECT_EQ(header, "step,t,p0_ux,p0_uy,p0_sigma11,p0_sigma22,p0_sigma12,p0_von_mises,p0_beta");
  int rows = 0;
  while (std::getline(probes, row)) ++rows;
  EXPECT_EQ(rows, 3);
}

TEST(RunOutput, ResumeRemovesTheSolutionFilesOfLaterSteps) {
  // Whatever process count wrote them: one-process VTUs, pieces and .pvtu files
  // of steps after the checkpoint's belong to the lost part of the run.
  const fs::path dir = temp_dir("resume_vtu");
  const Ran r = run_case(pressed_block("\"block\"", ""), dir);
  for (const char* f : {"solution_00002_p0000.vtu", "solution_00002_p0001.vtu", "solution_00002.pvtu",
                        "solution_00001_p0000.vtu"})
    std::ofstream(dir / f) << "x";
  TimeStepper stepper(r.c.problem, r.c.solvers);
  stepper.step();
  RunOutput out(stepper, r.c.output);
  out.resume(1, {{0.0, "solution_00000.vtu"}, {0.5, "solution_00001.vtu"}}, {});
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"history.csv", "probes.csv", "summary.json", "solution.pvd",
                                                  "solution_00000.vtu", "solution_00001.vtu",
                                                  "solution_00001_p0000.vtu"}));
  EXPECT_EQ(read_all(dir / "solution.pvd").find("solution_00002"), std::string::npos);
  std::ifstream history(dir / "history.csv");
  std::string line;
  int rows = -1;
  while (std::getline(history, line)) ++rows;
  EXPECT_EQ(rows, 1);
}

TEST(RunOutput, TributaryMeasures) {
  // 3D: the bottom face of the unit cube, 2 × 2 squares of two triangles each.
  const Mesh box = make_box({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  const std::vector<double> m = tributary_measures(box, {"bottom"});
  double sum = 0, centre = 0;
  for (int i = 0; i < box.n_nodes(); ++i) {
    sum += m[i];
    if (std::abs(box.node(i)[0] - 0.5) + std::abs(box.node(i)[1] - 0.5) + std::abs(box.node(i)[2]) < 1e-12)
      centre = m[i];
    if (box.node(i)[2] > 1e-12) {
      EXPECT_EQ(m[i], 0.0);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-14);
  EXPECT_NEAR(centre, 0.25, 1e-14);  // the interior node's share: h² whatever the diagonals
}

TEST(RunOutput, OldFieldNameDamageMeansBeta) {
  const fs::path dir = temp_dir("alias");
  run_case(pressed_block("\"block\"", "fields = [\"damage\", \"contact_pressure\"]\n"), dir);
  const auto a = read_vtu_arrays(dir / "solution_00001.vtu");
  EXPECT_EQ(a.count("beta"), 1u);
  EXPECT_EQ(a.count("contact_pressure"), 1u);
  EXPECT_EQ(a.count("displacement"), 0u);
}

TEST(RunOutput, CompressionNoneWritesRawData) {
  const fs::path dir = temp_dir("none");
  run_case(pressed_block("\"block\"", "compression = \"none\"\n"), dir);
  const std::string f = read_all(dir / "solution_00002.vtu");
  EXPECT_EQ(f.find("compressor"), std::string::npos);
  const fs::path dir2 = temp_dir("zlib");
  run_case(pressed_block("\"block\"", ""), dir2);
  EXPECT_NE(read_all(dir2 / "solution_00002.vtu").find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_EQ(read_vtu_arrays(dir / "solution_00002.vtu"), read_vtu_arrays(dir2 / "solution_00002.vtu"));
}

TEST(RunOutput, SummaryIsValidJsonWhateverTheNamesHold) {
  // An output path with a quote, a backslash, control characters and non-ASCII;
  // a command line with a byte that is not UTF-8. (The case name held them too
  // until issue 26 item 16 made it one safe path component.)
  const std::string name = "we.ird-name_1";
  const fs::path dir = temp_dir("sum \"q\" \\ b\x02 é");
  const std::vector<std::string> argv = {"vpcontact", "run", "x.toml", "-o", dir.string(), "bad\xff"};
  const Ran r = run_case(pressed_block(R"("we.ird-name_1")", ""), dir, argv);
  ASSERT_EQ(r.c.problem->name, name);
  const std::string text = read_all(dir / "summary.json");
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(text)) << text;
  EXPECT_EQ(j["case"], name);
  // The existing keys, as the plot script and the tests read them.
  for (const char* key : {"dimension", "mesh", "unknowns", "elasticity", "viscoplastic_law", "damage_source", "kappa",
                          "final_time", "steps", "time_step", "final", "checks", "probes", "timing_seconds",
                          "setup_seconds", "factorizations"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["steps"], 2);
  EXPECT_EQ(j["dimension"], 2);
  EXPECT_EQ(j["checks"]["all_steps_ok"], true);
  EXPECT_NEAR(j["final"]["total_contact_force"].get<double>(), 3.0, 1e-9);
  EXPECT_EQ(j["probes"][0][0], 1.0);
  EXPECT_FALSE(j.contains("engine"));
  // Where the memory goes (Linux: /proc/self/status): each stage's resident size within its peak,
  // the peaks never falling from stage to stage, one rank's peak at the end.
  const auto& mem = j["memory_bytes"];
  double last_peak = 0;
  for (const char* stage : {"mesh", "assembly", "factor_K", "factor_H", "contact", "end"}) {
    const double resident = mem[stage]["resident"].get<double>(), peak = mem[stage]["peak"].get<double>();
    EXPECT_GT(resident, 1e6) << stage;
    EXPECT_LE(resident, peak) << stage;
    EXPECT_GE(peak, last_peak) << stage;
    last_peak = peak;
  }
  ASSERT_EQ(mem["peak_per_rank"].size(), 1u);
  EXPECT_EQ(mem["peak_per_rank"][0].get<double>(), mem["end"]["peak"].get<double>());
  // What made the run.
  const auto& v = j["vpcontact"];
  EXPECT_FALSE(v["version"].get<std::string>().empty());
  EXPECT_FALSE(v["git_commit"].get<std::string>().empty());
  ASSERT_EQ(v["command_line"].size(), argv.size());
  for (std::size_t i = 0; i + 1 < argv.size(); ++i) EXPECT_EQ(v["command_line"][i], argv[i]);
  EXPECT_EQ(v["command_line"][5], "bad\xEF\xBF\xBD");  // the stray byte: U+FFFD
  EXPECT_TRUE(std::regex_match(v["date"].get<std::string>(),
                               std::regex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}Z")));
  // Round trip: what nlohmann writes back parses to the same document.
  EXPECT_EQ(nlohmann::json::parse(j.dump()), j);
}

TEST(RunOutput, Iso8601Utc) {
  EXPECT_EQ(iso8601_utc(std::chrono::system_clock::from_time_t(0)), "1970-01-01T00:00:00Z");
  EXPECT_EQ(iso8601_utc(std::chrono::system_clock::from_time_t(1700000000)), "2023-11-14T22:13:20Z");
}

}  // namespace
}  // namespace vpc
