// Checkpoints (format, checksum, fallback to an older good file), the stepper's
// checkpoints (in the numbering of the mesh as read: on one process exactly its
// snapshot, in the version-4 file; in pieces as several processes write them, read
// back whole or by blocks) and snapshot/restore and step halving.
#include "../../file_damage.hpp"
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "io/checkpoint_file.hpp"
#include "io/output_files.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>

namespace vpc {
namespace {

namespace fs = std::filesystem;

fs::path ckpt_dir(const std::string& name) { return test::fresh_dir("vpc_ckpt_", name); }

std::shared_ptr<Problem> small_2d() { return load_case("paper-2d", {.steps = 10}, {.cells = 10}).problem; }

/// test::checkpoint_of with PVD entries and totals to carry.
Checkpoint checkpoint_of(const TimeStepper& s) {
  RunTotals totals;
  totals.max_contact_iterations = 3;
  totals.seconds_output = 0.25;
  Checkpoint c = test::checkpoint_of(s);
  c.pvd = {{0.0, "solution_00000.vtu"}, {0.5, "x.vtu"}};
  c.totals = totals;
  return c;
}

/// Runs both steppers to the end: their states must stay bit-identical.
void expect_same_continuation(TimeStepper& a, TimeStepper& b) {
  while (!a.done()) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.state().u, b.state().u);
  EXPECT_EQ(a.state().beta, b.state().beta);
  EXPECT_EQ(a.state().lambda, b.state().lambda);
  ASSERT_EQ(a.state().sigma.size(), b.state().sigma.size());
  for (std::size_t i = 0; i < a.state().sigma.size(); ++i) EXPECT_EQ(a.state().sigma[i].c, b.state().sigma[i].c);
}

TEST(Checkpoint, RoundTripIsExact) {
  TimeStepper s(small_2d());
  for (int i = 0; i < 3; ++i) s.step();
  const fs::path dir = ckpt_dir("roundtrip");
  const fs::path file = write_checkpoint(dir, checkpoint_of(s));
  EXPECT_EQ(file.filename(), "checkpoint_00003.bin");
  const Checkpoint c = read_checkpoint(file);
  EXPECT_EQ(c.case_name, "paper-2d");
  EXPECT_EQ(c.fingerprint, problem_fingerprint(s));
  EXPECT_EQ(c.snapshot.state.n, 3);
  EXPECT_EQ(c.snapshot.state.t, s.state().t);
  EXPECT_EQ(c.snapshot.state.u, s.state().u);
  EXPECT_EQ(c.snapshot.state.beta, s.state().beta);
  EXPECT_EQ(c.snapshot.state.lambda, s.state().lambda);
  ASSERT_EQ(c.snapshot.state.z.size(), s.state().z.size());
  for (size_t i = 0; i < c.snapshot.state.z.size(); ++i) EXPECT_EQ(c.snapshot.state.z[i].c, s.state().z[i].c);
  EXPECT_EQ(c.pvd.size(), 2u);
  EXPECT_EQ(c.pvd[1].second, "x.vtu");
  EXPECT_EQ(c.totals.max_contact_iterations, 3);
  EXPECT_EQ(c.totals.seconds_output, 0.25);
}

TEST(Checkpoint, RestoredRunIsBitIdentical) {
  TimeStepper a(small_2d()), b(small_2d());
  for (int i = 0; i < 4; ++i) a.step();
  b.restore(read_checkpoint(write_checkpoint(ckpt_dir("restore"), checkpoint_of(a))).snapshot);
  expect_same_continuation(a, b);
}

// The primal contact solver (issue 14) keeps its factor of K with the last active set: a
// resumed run factors afresh, and CHOLMOD gives the same factor on the same matrix, so the
// continuation is bit-identical too (the whole-face case: the set changes at most steps).
TEST(Checkpoint, RestoredPrimalContactRunIsBitIdentical) {
  const auto problem = [] {
    Case c = load_case("foundation-3d", {.steps = 10}, {.cells = 4});
    c.solvers.contact = "primal-active-set";
    return c;
  };
  const Case ca = problem(), cb = problem();
  TimeStepper a(ca.problem, ca.solvers), b(cb.problem, cb.solvers);
  for (int i = 0; i < 4; ++i) a.step();
  b.restore(read_checkpoint(write_checkpoint(ckpt_dir("restore_primal"), checkpoint_of(a))).snapshot);
  expect_same_continuation(a, b);
  EXPECT_GT(a.state().lambda.size(), 0);
}

TEST(Checkpoint, DamagedNewestFallsBackToTheOlderOne) {
  TimeStepper s(small_2d());
  const fs::path dir = ckpt_dir("damaged");
  s.step();
  write_checkpoint(dir, checkpoint_of(s));
  s.step();
  const fs::path newest = write_checkpoint(dir, checkpoint_of(s));
  {  // flip one byte of the payload
    std::fstream f(newest, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    char c;
    f.read(&c, 1);
    f.seekp(100);
    c = static_cast<char>(c ^ 0x5a);
    f.write(&c, 1);
  }
  std::vector<std::string> skipped;
  const auto found = find_checkpoint(dir, problem_fingerprint(s), &skipped);
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->snapshot.state.n, 1);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find("checksum mismatch"), std::string::npos) << skipped[0];
}

TEST(Checkpoint, BadFilesAreRejectedWithAReason) {
  TimeStepper s(small_2d());
  const fs::path dir = ckpt_dir("bad");
  const fs::path file = write_checkpoint(dir, checkpoint_of(s));
  const fs::path cut = dir / "checkpoint_00007.bin";
  fs::copy_file(file, cut);
  fs::resize_file(cut, fs::file_size(file) - 10);
  EXPECT_THROW(read_checkpoint(cut), Error);
  try {
    read_checkpoint(cut);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  const fs::path junk = dir / "checkpoint_00009.bin";
  std::ofstream(junk) << "not a checkpoint";
  try {
    read_checkpoint(junk);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a vpcontact checkpoint"), std::string::npos) << e.what();
  }
  // Another problem's checkpoint is not taken.
  TimeStepper other(load_case("paper-2d", {.steps = 10}, {.cells = 5}).problem);
  std::vector<std::string> skipped;
  EXPECT_FALSE(find_checkpoint(dir, problem_fingerprint(other), &skipped).has_value());
  EXPECT_EQ(skipped.size(), 3u);
  EXPECT_THROW(other.restore(read_checkpoint(file).snapshot), Error);  // sizes differ
}

TEST(Checkpoint, KeepsOnlyTheNewest) {
  TimeStepper s(small_2d());
  const fs::path dir = ckpt_dir("keep");
  for (int i = 0; i < 5; ++i) {
    s.step();
    write_checkpoint(dir, checkpoint_of(s), 2);
  }
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == ".bin";
  EXPECT_EQ(n, 2);
  EXPECT_TRUE(fs::exists(dir / "checkpoint_00005.bin"));
  EXPECT_TRUE(fs::exists(dir / "checkpoint_00004.bin"));
}

TEST(Checkpoint, ANewTimelineReplacesTheOldOnes) {
  // A run that goes back to step 1 (a fresh run, or a resume from an older
  // checkpoint) must not leave later-step checkpoints for --resume to pick.
  TimeStepper s(small_2d());
  const fs::path dir = ckpt_dir("timeline");
  const Snapshot start = s.snapshot();
  for (int i = 0; i < 4; ++i) {
    s.step();
    write_checkpoint(dir, checkpoint_of(s), 2);
  }
  s.restore(start);
  s.step();
  write_checkpoint(dir, checkpoint_of(s), 2);
  EXPECT_TRUE(fs::exists(dir / "checkpoint_00001.bin"));
  EXPECT_FALSE(fs::exists(dir / "checkpoint_00003.bin"));
  EXPECT_FALSE(fs::exists(dir / "checkpoint_00004.bin"));
  remove_run_outputs(dir);  // what a fresh run does
  EXPECT_FALSE(fs::exists(dir / "checkpoint_00001.bin"));
  std::vector<std::string> skipped;
  EXPECT_FALSE(find_checkpoint(dir, problem_fingerprint(s), &skipped).has_value());
}

/// Both solvers by penalty–duality: their warm states are part of the checkpoint.
SolverChoice penalty_duality() {
  SolverChoice c;
  c.contact = c.damage = "penalty-duality";
  return c;
}

TEST(StepperCheckpoint, OneProcessWritesItsSnapshotInTheSameFormat) {
  TimeStepper s(small_2d(), penalty_duality());
  for (int i = 0; i < 3; ++i) s.step();
  ASSERT_GT(s.snapshot().contact_warm.size(), 0);
  ASSERT_GT(s.snapshot().damage_warm.size(), 0);
  const Checkpoint c = checkpoint_of(s);
  const fs::path a = ckpt_dir("stepper_a"), b = ckpt_dir("stepper_b");
  write_checkpoint(s, a, c.case_name, c.pvd, c.totals);
  write_checkpoint(b, c);
  const std::string written = test::read_bytes(a / "checkpoint_00003.bin");
  EXPECT_FALSE(written.empty());
  EXPECT_EQ(written, test::read_bytes(b / "checkpoint_00003.bin"));
}

TEST(StepperCheckpoint, TheFingerprintIsTheKeysHashWithoutTheTimes) {
  TimeStepper s(small_2d());
  const Problem& p = s.problem();
  const std::string key = fmt::format("case={}|dimension={}|nodes={}|cells={}|free dofs={}|contact nodes={}|"
                                      "kappa={:.17g}|elasticity={}|G={}|phi={}",
                                      p.name, p.mesh.dim(), p.mesh.n_nodes(), p.mesh.n_cells(), s.dofs().n_free(),
                                      s.part().n_contact, p.kappa, p.elasticity.name(), p.law->describe(),
                                      p.source->describe());
  EXPECT_EQ(problem_key(s), key);
  std::uint64_t h = 1469598103934665603ull;
  for (char ch : key) h = (h ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
  EXPECT_EQ(problem_fingerprint(s), h);
  // T and the steps are not part of it (a run continues to a later T); κ is, and the
  // difference names it.
  TimeStepper longer(load_case("paper-2d", {.sets = {"time.T=2"}, .steps = 20}, {.cells = 10}).problem);
  EXPECT_EQ(problem_fingerprint(longer), problem_fingerprint(s));
  TimeStepper other(load_case("paper-2d", {.kappa = 0.5, .steps = 10}, {.cells = 10}).problem);
  EXPECT_NE(problem_fingerprint(other), problem_fingerprint(s));
  EXPECT_EQ(problem_key_difference(problem_key(s), problem_key(other)),
            fmt::format("kappa = {:.17g} in the checkpoint, 0.5 in this case", p.kappa));
}

TEST(StepperCheckpoint, ResumedRunIsBitIdentical) {
  TimeStepper a(small_2d(), penalty_duality()), b(small_2d(), penalty_duality());
  for (int i = 0; i < 4; ++i) a.step();
  const fs::path dir = ckpt_dir("stepper_resume");
  RunTotals totals;
  totals.max_damage_iterations = 7;
  write_checkpoint(a, dir, "paper-2d", {{0.0, "solution_00000.vtu"}}, totals);
  std::vector<std::string> skipped;
  const auto at = resume_from_checkpoint(b, dir, &skipped);
  ASSERT_TRUE(at.has_value());
  EXPECT_TRUE(skipped.empty());
  EXPECT_EQ(at->n, 4);
  EXPECT_EQ(at->t, a.state().t);
  ASSERT_EQ(at->pvd.size(), 1u);
  EXPECT_EQ(at->pvd[0].second, "solution_00000.vtu");
  EXPECT_EQ(at->totals.max_damage_iterations, 7);
  EXPECT_EQ(b.snapshot().u_free, a.snapshot().u_free);
  EXPECT_EQ(b.snapshot().contact_warm, a.snapshot().contact_warm);
  EXPECT_EQ(b.snapshot().damage_warm, a.snapshot().damage_warm);
  expect_same_continuation(a, b);
  // No checkpoint for this problem: nothing restored.
  TimeStepper other(load_case("paper-2d", {.steps = 10}, {.cells = 5}).problem);
  EXPECT_FALSE(resume_from_checkpoint(other, dir, &skipped).has_value());
  EXPECT_EQ(skipped.size(), 1u);
}

/// The payload and header of a file in the format docs/reliability.md describes, built here
/// independently of the writer: version 6 with the case's keys, the grid and the changes on
/// resume, or version 4 (earlier programs) without them.
std::string documented_file(std::uint32_t version) {
  std::string payload;
  auto put = [&](auto v) { payload.append(reinterpret_cast<const char*>(&v), sizeof v); };
  auto string = [&](const std::string& v) {
    put(std::uint64_t(v.size()));
    payload += v;
  };
  auto array = [&](std::initializer_list<double> v) {
    put(std::uint64_t(v.size()));
    for (double x : v) put(x);
  };
  string("k");
  put(std::uint64_t(0x0123456789abcdefull));
  string("case=k");
  if (version == 6) {
    put(std::uint64_t(1));
    string("elasticity.E");
    string("1000");
  }
  put(std::int64_t(7));
  put(0.5);
  if (version == 6) {  // no grid: the levels are stored
    put(0.0);
    put(std::int64_t(0));
  }
  array({1, 2});
  array({0.25});
  array({3});
  array({2});
  array({0, 1, 2, 3, 4, 5});
  array({0, -1, -2, -3, -4, -5});
  array({10, 11, 12, 13, 14, 15});
  array({});
  array({});
  array({0, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5});
  array({0.125, 2, 1, 0, 3, 4});
  put(std::uint64_t(1));
  put(0.5);
  string("a.vtu");
  for (int i = 0; i < 7; ++i) put(0.0);
  put(std::int64_t(4));
  put(std::int64_t(0));
  put(std::uint8_t(0));
  put(std::int64_t(9));
  if (version == 6) {
    put(std::uint64_t(1));
    put(std::int64_t(3));
    string("time.T");
    string("1");
    string("2");
  }
  std::uint64_t h = 1469598103934665603ull;
  for (char ch : payload) h = (h ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
  std::string file("VPCCKPT\0", 8);
  const std::uint32_t reserved = 0;
  file.append(reinterpret_cast<const char*>(&version), 4);
  file.append(reinterpret_cast<const char*>(&reserved), 4);
  const std::uint64_t size = payload.size();
  file.append(reinterpret_cast<const char*>(&size), 8);
  file.append(reinterpret_cast<const char*>(&h), 8);
  return file + payload;
}

/// The checkpoint documented_file holds.
Checkpoint documented_checkpoint() {
  Checkpoint c;
  c.case_name = "k";
  c.fingerprint = 0x0123456789abcdefull;
  c.problem_key = "case=k";
  c.case_keys = {{"elasticity.E", "1000"}};
  c.times = {0, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5};
  c.step_control = Eigen::Vector<double, 6>(0.125, 2, 1, 0, 3, 4);
  State& s = c.snapshot.state;
  s.n = 7;
  s.t = 0.5;
  s.u = Eigen::Vector2d(1, 2);
  s.beta = Eigen::Matrix<double, 1, 1>(0.25);
  s.lambda = Eigen::Matrix<double, 1, 1>(3);
  c.snapshot.u_free = Eigen::Matrix<double, 1, 1>(2);
  s.sigma.resize(1);
  s.eps.resize(1);
  s.z.resize(1);
  for (int j = 0; j < 6; ++j) s.sigma[0].c[j] = j, s.eps[0].c[j] = -j, s.z[0].c[j] = 10 + j;
  c.pvd = {{0.5, "a.vtu"}};
  c.totals.max_contact_iterations = 4;
  c.totals.all_ok = false;
  c.totals.last_n_active = 9;
  c.totals.resume_changes = {{3, "time.T", "1", "2"}};
  return c;
}

TEST(StepperCheckpoint, TheVersionSixBytesAreAsDocumented) {
  const fs::path file = write_checkpoint(ckpt_dir("bytes"), documented_checkpoint());
  EXPECT_EQ(test::read_bytes(file), documented_file(6));
  const Checkpoint back = read_checkpoint(file);
  EXPECT_EQ(back.case_keys, documented_checkpoint().case_keys);
  ASSERT_EQ(back.totals.resume_changes.size(), 1u);
  EXPECT_EQ(back.totals.resume_changes[0].key, "time.T");
  EXPECT_EQ(back.totals.resume_changes[0].after, "2");
}

// A checkpoint of an earlier program (version 4: no case keys) is still read whole, but a resume
// refuses it, saying why: its case cannot be compared with this one.
TEST(StepperCheckpoint, AVersionFourFileIsReadButNotResumed) {
  const fs::path dir = ckpt_dir("v4");
  const fs::path file = dir / "checkpoint_00007.bin";
  std::ofstream(file, std::ios::binary) << documented_file(4);
  const Checkpoint c = read_checkpoint(file), expected = documented_checkpoint();
  EXPECT_TRUE(c.case_keys.empty());
  EXPECT_EQ(c.times, expected.times);
  EXPECT_EQ(c.snapshot.state.u, expected.snapshot.state.u);
  EXPECT_EQ(c.snapshot.state.z[0].c, expected.snapshot.state.z[0].c);
  EXPECT_EQ(c.pvd, expected.pvd);
  EXPECT_EQ(c.totals.last_n_active, 9);
  EXPECT_TRUE(c.totals.resume_changes.empty());
  TimeStepper s(small_2d());
  try {
    resume_from_checkpoint(s, dir);
    ADD_FAILURE() << "a version-4 checkpoint was resumed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is of format version 4, written by an earlier vpcontact that did not record "
                                         "its case"),
              std::string::npos)
        << e.what();
  }
}

// A uniform grid's checkpoint stores the grid, not t_0 … t_n: its size does not grow with the
// steps (issue 48: 8 bytes a step, 800 MB a checkpoint at 10^8 steps). Its levels read back
// bit for bit. A grid that is not uniform still stores its levels.
TEST(StepperCheckpoint, AUniformGridIsStoredInsteadOfItsLevels) {
  auto size_at = [](const std::shared_ptr<Problem>& p, int n, const std::string& name) {
    TimeStepper s(p);
    for (int i = 0; i < n; ++i) s.step();
    const fs::path dir = ckpt_dir(name);
    write_checkpoint(s, dir, "paper-2d", {}, {});
    const fs::path file = dir / fmt::format("checkpoint_{:05d}.bin", n);
    const Checkpoint c = read_checkpoint(file);
    EXPECT_EQ(c.times, s.times());
    EXPECT_EQ(c.grid.steps > 0, p->uniform_steps());
    return fs::file_size(file);
  };
  const auto uniform = small_2d();
  EXPECT_EQ(size_at(uniform, 1, "grid1"), size_at(uniform, 8, "grid8"));
  const auto listed = load_case("paper-2d", {.sets = {"time.dt=[0.1, 0.1, 0.2, 0.2, 0.4]"}}, {.cells = 10}).problem;
  EXPECT_EQ(size_at(listed, 4, "levels4"), size_at(listed, 1, "levels1") + 3 * 8);
  // The levels of a uniform grid are Problem::time_at's (T exactly at N).
  const UniformGrid g{1.0, 3};
  EXPECT_EQ(g.levels(3), (std::vector<double>{0, 1.0 / 3, 2 * (1.0 / 3), 1.0}));
}

// A file is written array by array as a process forms them (checkpoint_file::FileWriter): a
// write that stops before commit (an error on another process, an exception) leaves neither
// the file nor its temporary, and a file that cannot be opened takes every array and fails at
// commit, so that its process goes on with the others' collective steps in between.
TEST(CheckpointFile, AnUncommittedWriteLeavesNothingAndErrorsWaitForTheCommit) {
  using namespace checkpoint_file;
  const fs::path dir = ckpt_dir("writer");
  const std::vector<std::pair<double, std::string>> pvd{{0.5, "a.vtu"}};
  const RunTotals totals;
  FileContent f;
  f.case_name = "k";
  f.n = 1;
  f.pvd = &pvd;
  f.totals = &totals;
  std::array<std::vector<double>, kArrays> content;  // one node of 2 dofs, no cell, step 1
  content[kU] = {1, 2};
  content[kBeta] = {0.25};
  content[kTimes] = {0, 0.5};
  auto write_all = [&](FileWriter& w) {
    for (int a = 0; a < arrays_in_file(1); ++a) w.array(static_cast<Array>(a), content[a]);
  };
  {
    FileWriter w(dir / "checkpoint_00001.bin", f);
    w.array(kU, content[kU]);
  }
  EXPECT_TRUE(fs::is_empty(dir));
  FileWriter nowhere(dir / "missing" / "checkpoint_00001.bin", f);
  write_all(nowhere);
  try {
    nowhere.commit();
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir));
  // The same arrays into a file that can be written: the file write_file writes.
  FileWriter w(dir / "checkpoint_00001.bin", f);
  write_all(w);
  const PieceSum sum = w.commit();
  for (int a = 0; a < kArrays; ++a) f.arrays[a] = content[a];
  EXPECT_EQ(write_file(dir / "whole.bin", f), sum);
  EXPECT_EQ(test::read_bytes(dir / "checkpoint_00001.bin"), test::read_bytes(dir / "whole.bin"));
  CheckpointFile back(dir / "checkpoint_00001.bin", true);
  EXPECT_EQ(back.read(kU), Eigen::Vector2d(1, 2));
  EXPECT_EQ(back.pvd, pvd);
}

fs::path piece(const fs::path& dir, int n, int r, int p) {
  return dir / fmt::format("checkpoint_{:05d}.p{:04d}-of-{:04d}.bin", n, r, p);
}

using test::flip_a_byte;

void expect_same(const Checkpoint& a, const Checkpoint& b) {
  const State &x = a.snapshot.state, &y = b.snapshot.state;
  EXPECT_EQ(a.case_name, b.case_name);
  EXPECT_EQ(a.fingerprint, b.fingerprint);
  EXPECT_EQ(x.n, y.n);
  EXPECT_EQ(x.t, y.t);
  EXPECT_EQ(x.u, y.u);
  EXPECT_EQ(x.beta, y.beta);
  EXPECT_EQ(x.lambda, y.lambda);
  EXPECT_EQ(a.snapshot.u_free, b.snapshot.u_free);
  EXPECT_EQ(a.snapshot.contact_warm, b.snapshot.contact_warm);
  EXPECT_EQ(a.snapshot.damage_warm, b.snapshot.damage_warm);
  for (auto [s, t] : {std::pair{&x.sigma, &y.sigma}, std::pair{&x.eps, &y.eps}, std::pair{&x.z, &y.z}}) {
    ASSERT_EQ(s->size(), t->size());
    for (std::size_t i = 0; i < s->size(); ++i) EXPECT_EQ((*s)[i].c, (*t)[i].c);
  }
  EXPECT_EQ(a.pvd, b.pvd);
  EXPECT_EQ(a.totals.max_contact_iterations, b.totals.max_contact_iterations);
  EXPECT_EQ(a.totals.seconds_output, b.totals.seconds_output);
}

// Pieces as 3 processes write them (here one process writes all three): each its
// third of the node and cell arrays; read back whole, they are the one-process checkpoint.
TEST(CheckpointPieces, ThreePiecesHoldTheWholeStateEachItsShare) {
  TimeStepper s(small_2d(), penalty_duality());
  for (int i = 0; i < 3; ++i) s.step();
  const Checkpoint c = checkpoint_of(s);
  const fs::path dir = ckpt_dir("pieces"), one = ckpt_dir("pieces_one");
  write_checkpoint(s, dir, c.case_name, c.pvd, c.totals, 3);
  write_checkpoint(s, one, c.case_name, c.pvd, c.totals);
  int n_files = 0;
  for (const auto& e : fs::directory_iterator(dir)) n_files += e.path().extension() == ".bin";
  EXPECT_EQ(n_files, 3);
  const fs::path first = dir / "checkpoint_00003.bin";
  ASSERT_TRUE(fs::exists(piece(dir, 3, 1, 3)));
  ASSERT_TRUE(fs::exists(piece(dir, 3, 2, 3)));
  expect_same(read_checkpoint(first), read_checkpoint(one / "checkpoint_00003.bin"));
  const auto total = static_cast<double>(fs::file_size(one / "checkpoint_00003.bin"));
  for (const fs::path& f : {first, piece(dir, 3, 1, 3), piece(dir, 3, 2, 3)}) {
    EXPECT_LT(fs::file_size(f), 1.1 * total / 3 + 1024) << f;
    EXPECT_GT(fs::file_size(f), 0.9 * total / 3) << f;
  }
  try {  // a piece is not a checkpoint by itself
    read_checkpoint(piece(dir, 3, 1, 3));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("piece 1 of 3, not a checkpoint's first file"), std::string::npos) << e.what();
  }
}

TEST(CheckpointPieces, ResumedFromPiecesIsBitIdentical) {
  TimeStepper a(small_2d(), penalty_duality()), b(small_2d(), penalty_duality());
  for (int i = 0; i < 4; ++i) a.step();
  const fs::path dir = ckpt_dir("pieces_resume");
  RunTotals totals;
  totals.max_damage_iterations = 5;
  write_checkpoint(a, dir, "paper-2d", {{0.0, "solution_00000.vtu"}}, totals, 4);
  std::vector<std::string> skipped;
  const auto at = resume_from_checkpoint(b, dir, &skipped);
  ASSERT_TRUE(at.has_value());
  EXPECT_TRUE(skipped.empty());
  EXPECT_EQ(at->n, 4);
  EXPECT_EQ(at->totals.max_damage_iterations, 5);
  ASSERT_EQ(at->pvd.size(), 1u);
  EXPECT_EQ(b.snapshot().u_free, a.snapshot().u_free);
  EXPECT_EQ(b.snapshot().contact_warm, a.snapshot().contact_warm);
  EXPECT_EQ(b.snapshot().damage_warm, a.snapshot().damage_warm);
  expect_same_continuation(a, b);
}

/// Checkpoints of steps 1 and 2 in 3 pieces; `damage` spoils step 2's; a resume then
/// takes step 1 and says why it passed over step 2.
void expect_step_1_because(const std::string& name, const std::function<void(const fs::path&)>& damage,
                           const std::string& reason) {
  TimeStepper s(small_2d()), b(small_2d());
  const fs::path dir = ckpt_dir(name);
  for (int i = 0; i < 2; ++i) {
    s.step();
    write_checkpoint(s, dir, "paper-2d", {}, {}, 3);
  }
  damage(dir);
  std::vector<std::string> skipped;
  const auto at = resume_from_checkpoint(b, dir, &skipped);
  ASSERT_TRUE(at.has_value()) << name;
  EXPECT_EQ(at->n, 1) << name;
  ASSERT_EQ(skipped.size(), 1u) << name;
  EXPECT_NE(skipped[0].find(reason), std::string::npos) << skipped[0];
  skipped.clear();  // reading the checkpoint whole says the same
  const auto found = find_checkpoint(dir, problem_fingerprint(s), &skipped);
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->snapshot.state.n, 1);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find(reason), std::string::npos) << skipped[0];
}

TEST(CheckpointPieces, AMissingOrDamagedPieceFallsBackToTheOlderCheckpoint) {
  expect_step_1_because("missing", [](const fs::path& d) { fs::remove(piece(d, 2, 2, 3)); },
                        "piece 2 of 3 ('checkpoint_00002.p0002-of-0003.bin') is missing");
  expect_step_1_because("flipped", [](const fs::path& d) { flip_a_byte(piece(d, 2, 1, 3)); },
                        "checkpoint_00002.p0001-of-0003.bin': checksum mismatch (damaged file)");
  expect_step_1_because("cut", [](const fs::path& d) { fs::resize_file(piece(d, 2, 2, 3), 100); },
                        "checkpoint_00002.p0002-of-0003.bin': 68 payload bytes, the header says");
  // A good piece of another write of step 2 (a crash between the pieces and piece 0
  // of a new timeline): not the piece that piece 0 lists.
  expect_step_1_because("stale",
                        [](const fs::path& d) {
                          TimeStepper other(small_2d(), penalty_duality());
                          for (int i = 0; i < 2; ++i) other.step();
                          const fs::path elsewhere = ckpt_dir("stale_elsewhere");
                          write_checkpoint(other, elsewhere, "paper-2d", {}, {}, 3);
                          fs::copy_file(piece(elsewhere, 2, 1, 3), piece(d, 2, 1, 3),
                                        fs::copy_options::overwrite_existing);
                        },
                        "not the piece that 'checkpoint_00002.bin' lists");
  // Piece 0 itself damaged.
  expect_step_1_because("first", [](const fs::path& d) { flip_a_byte(d / "checkpoint_00002.bin"); },
                        "checkpoint_00002.bin': checksum mismatch");
}

TEST(CheckpointPieces, KeepingTheNewestAndANewTimelineRemoveWholeCheckpoints) {
  TimeStepper s(small_2d());
  const fs::path dir = ckpt_dir("pieces_keep");
  const Snapshot start = s.snapshot();
  for (int i = 0; i < 4; ++i) {
    s.step();
    write_checkpoint(s, dir, "paper-2d", {}, {}, 3);
  }
  auto files = [&] {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
  };
  EXPECT_EQ(files(), (std::set<std::string>{"checkpoint_00003.bin", "checkpoint_00003.p0001-of-0003.bin",
                                            "checkpoint_00003.p0002-of-0003.bin", "checkpoint_00004.bin",
                                            "checkpoint_00004.p0001-of-0003.bin",
                                            "checkpoint_00004.p0002-of-0003.bin"}));
  // Back to step 3, now in 2 pieces (a resume on 2 processes): step 4 goes, and step 3's third piece.
  s.restore(start);
  for (int i = 0; i < 3; ++i) s.step();
  write_checkpoint(s, dir, "paper-2d", {}, {}, 2);
  EXPECT_EQ(files(), (std::set<std::string>{"checkpoint_00003.bin", "checkpoint_00003.p0001-of-0002.bin"}));
  // On one process: the version-4 file alone.
  write_checkpoint(s, dir, "paper-2d", {}, {});
  EXPECT_EQ(files(), (std::set<std::string>{"checkpoint_00003.bin"}));
  remove_run_outputs(dir);  // what a fresh run does
  write_checkpoint(s, dir, "paper-2d", {}, {}, 2);
  remove_run_outputs(dir);
  EXPECT_TRUE(files().empty());
}

/// A damage source that fails (NaN) the first time it is evaluated at t = 0.3,
/// like a solver that fails once and succeeds with a smaller step.
class FailsOnce final : public DamageSource {
 public:
  explicit FailsOnce(std::shared_ptr<std::atomic<int>> failures) : failures_(std::move(failures)) {}
  double rate(const PointState& s) const override {
    if (std::abs(s.t - 0.3) < 1e-12 && failures_->exchange(1) == 0) return std::nan("");
    return -0.01 * s.sigma.von_mises();
  }
  std::string describe() const override { return "fails once"; }
  std::shared_ptr<std::atomic<int>> failures_;
};

TEST(StepHalving, AFailedStepIsRetriedWithHalfSteps) {
  for (int halvings : {0, 1}) {
    auto p = small_2d();
    auto failures = std::make_shared<std::atomic<int>>(0);
    p->source = std::make_shared<FailsOnce>(failures);
    SolverChoice choice;
    choice.max_halvings = halvings;
    TimeStepper s(p, choice);
    StepReport failed;
    bool any_failed = false;
    while (!s.done()) {
      const StepReport r = s.step();
      if (!r.ok) {
        any_failed = true;
        failed = r;
        break;
      }
      if (r.substeps > 1) {
        EXPECT_EQ(halvings, 1);
        EXPECT_EQ(r.n, 4);  // the step from t = 0.3
        EXPECT_NEAR(r.t, 0.4, 1e-15);
        EXPECT_EQ(r.substeps, 2);
      }
    }
    if (halvings == 0) {
      EXPECT_TRUE(any_failed);
      EXPECT_EQ(failed.n, 4);
      EXPECT_FALSE(std::isfinite(s.state().beta.norm()) && failed.ok);
    } else {
      EXPECT_FALSE(any_failed);
      EXPECT_TRUE(s.done());
      EXPECT_GE(s.state().beta.minCoeff(), 0.0);
    }
  }
}

}  // namespace
}  // namespace vpc
