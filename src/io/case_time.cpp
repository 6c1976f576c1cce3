// [time]: the final time T and the time grid (problem/time_grid.hpp): uniform steps, a list or a
// formula of step sizes, or error-controlled steps (StepControl).
#include "io/case_readers.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"

namespace vpc::case_file {

/// The keys of [time] that only error-controlled steps (`tolerance`) take.
const std::vector<std::string>& step_control_keys() {
  static const std::vector<std::string> keys = {"dt_initial", "dt_min", "dt_max", "growth", "cut",
                                                "safety", "event_dt", "events", "max_rejections"};
  return keys;
}

/// [time]: T and one of
///   steps = N                    N uniform steps;
///   dt = k                       uniform steps of k (it must divide T);
///   dt = [k1, k2, …]             these steps (adding up to T), or with breakpoints = [b1, …]
///                                one step size per interval [0, b1], [b1, b2], …, [b_last, T];
///   dt = "formula in t"          t_{n+1} = t_n + k(t_n);
///   tolerance = e                error-controlled steps (problem/time_grid.hpp, StepControl),
///                                with dt_initial, dt_min, dt_max, growth, cut, safety, event_dt,
///                                events, max_rejections; breakpoints: times a step ends at.
void read_time(Section tm, Problem& p, const std::string& file) {
  if (!tm.exists()) fail("{}: missing section [time] (T and steps, dt or tolerance)", file);
  p.final_time = tm.number("T", 1.0);
  located(tm.where("T"), [&] { check_final_time(p.final_time); });
  const int given = tm.has("steps") + tm.has("dt") + tm.has("tolerance");
  if (given != 1)
    fail("{}: give exactly one of steps, dt (a step size, a list or a formula in t) and tolerance (error-controlled "
         "steps)", tm.where_section());
  std::vector<double> breakpoints;
  if (tm.has("breakpoints")) breakpoints = tm.numbers("breakpoints", 0);
  if (!tm.has("tolerance"))
    for (const auto& k : step_control_keys())
      if (tm.has(k)) fail("{}: applies to error-controlled steps only (give tolerance instead of steps or dt)", tm.where(k));
  if (tm.has("steps")) {
    if (!breakpoints.empty()) fail("{}: breakpoints need dt (a step size per interval) or tolerance", tm.where("breakpoints"));
    p.n_steps = tm.integer("steps");
    located(tm.where("steps"), [&] { check_n_steps(p.n_steps); });
  } else if (tm.has("tolerance")) {
    StepControl c;
    c.tolerance = tm.number("tolerance");
    c.dt_initial = tm.number("dt_initial", 0.0);
    c.dt_min = tm.number("dt_min", 0.0);
    c.dt_max = tm.number("dt_max", 0.0);
    c.growth = tm.number("growth", c.growth);
    c.cut = tm.number("cut", c.cut);
    c.safety = tm.number("safety", c.safety);
    c.event_dt = tm.number("event_dt", 0.0);
    c.max_rejections = tm.integer("max_rejections", c.max_rejections);
    if (tm.has("events")) {
      c.contact_events = c.damage_events = false;
      for (const std::string& e : tm.strings("events")) {
        if (e == "contact") c.contact_events = true;
        else if (e == "damage") c.damage_events = true;
        else fail("{}: unknown event {}; expected some of: contact, damage", tm.where("events"), quote(e));
      }
    }
    c.landings = breakpoints;
    located(tm.where_section(), [&] { (void)c.completed(p.final_time); });
    p.step_control = std::move(c);
    p.n_steps = 0;
  } else {
    const toml::node* dt = tm.get("dt");
    if (dt->is_array()) {
      const std::vector<double> k = tm.numbers("dt", 0);
      p.set_fixed_grid(located(tm.where("dt"), [&] {
        return breakpoints.empty() && !tm.has("breakpoints") ? fixed_grid_of_steps(p.final_time, k)
                                                             : fixed_grid_of_intervals(p.final_time, breakpoints, k);
      }));
    } else if (dt->is_string()) {
      if (tm.has("breakpoints")) fail("{}: breakpoints need a list of step sizes in dt", tm.where("breakpoints"));
      const auto k = tm.expression("dt", Expression::Kind::SpaceTime);
      if (k->uses_position()) fail("{}: the step size k(t) is a formula in t only", tm.where("dt"));
      p.set_fixed_grid(located(tm.where("dt"), [&] {
        return fixed_grid_of_formula(p.final_time, [&](double t) { return (*k)({0, 0, 0}, t); });
      }));
    } else {
      const double k = tm.number("dt");
      if (tm.has("breakpoints")) {  // steps of k that end at each breakpoint
        const std::vector<double> each(breakpoints.size() + 1, k);
        p.set_fixed_grid(
            located(tm.where("dt"), [&] { return fixed_grid_of_intervals(p.final_time, breakpoints, each); }));
      } else {
        p.n_steps = located(tm.where("dt"), [&] { return steps_of_time_step(p.final_time, k); });
      }
    }
  }
  tm.finish();
}

}  // namespace vpc::case_file
