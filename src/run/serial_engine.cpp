// The serial engine: TimeStepper, RunOutput and the checkpoints of io/checkpoint.hpp.
#include "io/checkpoint.hpp"
#include "io/run_output.hpp"
#include "run/progress.hpp"
#include "run/run_case.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <optional>

namespace vpc {

namespace {

class SerialEngine final : public Engine {
 public:
  explicit SerialEngine(Case c) : case_(std::move(c)), stepper_(case_.problem, case_.solvers) {}

  bool done() const override { return stepper_.done(); }
  StepReport step() override { return stepper_.step(); }
  int n_steps() const override { return stepper_.problem().n_steps; }
  double tolerance() const override { return case_.solvers.residual_tolerance; }

  void open_output() override {
    output_.emplace(stepper_, case_.output);
    fingerprint_ = problem_fingerprint(stepper_);
  }
  const std::filesystem::path& directory() const override { return output_->directory(); }
  void start() override { output_->start(); }
  void record(const StepReport& r) override { output_->record(r); }
  void finish(double wall_seconds) override { output_->finish(wall_seconds); }
  void checkpoint() override {
    write_checkpoint(output_->directory(),
                     {case_.name, fingerprint_, stepper_.snapshot(), output_->pvd_entries(), output_->totals()});
  }
  std::optional<ResumedAt> resume(const std::filesystem::path& dir, std::vector<std::string>& skipped) override {
    auto saved = find_checkpoint(dir, fingerprint_, &skipped);
    if (!saved) return std::nullopt;
    stepper_.restore(saved->snapshot);
    output_->resume(saved->snapshot.state.n, saved->pvd, saved->totals);
    return ResumedAt{saved->snapshot.state.n, saved->snapshot.state.t};
  }

  /// What set-up found.
  void describe() const {
    const auto& p = stepper_.problem();
    const auto [hmin, hmax] = p.mesh.size_range();
    fmt::print("  mesh: d = {}, {} nodes, {} cells, h in [{:.3g}, {:.3g}]; {} free displacement dofs, {} contact "
               "nodes\n",
               p.mesh.dim(), p.mesh.n_nodes(), p.mesh.n_cells(), hmin, hmax, stepper_.dofs().n_free(),
               stepper_.contact_nodes().size());
    describe_data(p, case_.solvers, stepper_.setup_seconds());
  }

 private:
  Case case_;
  TimeStepper stepper_;
  std::optional<RunOutput> output_;
  std::uint64_t fingerprint_ = 0;
};

}  // namespace

void describe_data(const Problem& p, const SolverChoice& solvers, double setup_seconds) {
  fmt::print("  Γ1 (clamped): {}; Γ3 (contact): {}\n", fmt::join(p.clamped, ", "), fmt::join(p.contact.parts, ", "));
  fmt::print("  elasticity: {} (E = {}, nu = {}); G: {}; phi: {}\n", p.elasticity.name(), p.elasticity.young(),
             p.elasticity.poisson(), p.law->describe(), p.source->describe());
  fmt::print("  kappa = {}; T = {}, k = {}, N = {}; solvers: contact {}, damage {}; setup {:.3f} s\n", p.kappa,
             p.final_time, p.step(), p.n_steps, solvers.contact, solvers.damage, setup_seconds);
  std::fflush(stdout);
}

std::unique_ptr<Engine> set_up_serial(const CaseLoader& load, const RunOptions& o) {
  begin_run(o);
  stop_if_interrupted();
  Case c = load({});
  StageLog log(o.quiet);
  c.solvers.max_halvings = o.halvings;
  c.solvers.on_setup_stage = [log](const std::string& stage, double seconds) {  // a copy: it outlives set-up
    log(stage, seconds);
    if (seconds >= 0) stop_if_interrupted();
  };
  auto engine = std::make_unique<SerialEngine>(std::move(c));
  if (!o.quiet) engine->describe();
  return engine;
}

}  // namespace vpc
