#pragma once
// The continuation of a branch of steady fronts in σ_d (docs/fronts.md §4 steps 2–7, §10.8), written once for every
// front model: the second front by a natural step, then pseudo-arclength in (σ_d, c/c_s) with the secant of the
// last two fronts as predictor, the step controlled by the corrector's iterations and capped to keep a quarter of
// the gap σ_d − σ_c^d, every point polished at fixed σ_d. Internal to continuum/.
//
// `Derived` (CRTP) is the model's continuation; it supplies what differs between models:
//   Front solve_at(double σ_d, const Front* guess)                         the fixed-σ_d solve
//   Front correct(double σ_p, double c_p, const front_solver::Arclength&)  one corrector from cur_ with σ_d free
//   void keep(const Front&)                                                 a front the branch keeps (profiles)
//   bool stop_requested()                                                   polled before every solve
//   bool reached_own_end()                                                  an end besides σ_c^d (or false)
// and its own first front, limiting front and admissibility checks. `Branch` has points, end, reason, folds,
// c_min, sigma_d_at_c_min, c_min_at_end, last; `Options` initial_step, max_step, min_step, target_newton,
// end_gap, max_points.
#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>

#include "continuum/front_solver.hpp"

namespace slipfront::continuum::front_solver {

template <class Derived, class Front, class Branch, class Options>
class SigmaContinuation {
 public:
  bool ended_at_saddle_node() const { return br_.end == BranchEnd::saddle_node; }
  Branch take_branch() { return std::move(br_); }

  // §4 steps 3–7: pseudo-arclength until an end of the branch (or max_points).
  void follow() {
    while (static_cast<int>(br_.points.size()) < o_.max_points) {
      const Secant t = secant(prev_.sigma_d, prev_.c, cur_.sigma_d, cur_.c, cs_, t_sigma_before_, br_.folds);
      if (reached_end() || self().stop_requested()) break;
      Front next = predict_and_correct(t);
      if (next.status == FrontStatus::stopped) {
        stop(BranchEnd::stopped, "stopped on request in a solve after " + std::to_string(br_.points.size()) +
                                     " fronts: the branch is partial, c_min not computed");
        break;
      }
      if (next.status != FrontStatus::converged) {
        stop(end_of(next.status), "continuation stalls at sigma_d = " + core::format_number(cur_.sigma_d) +
                                      " (step < min_step): " + std::string(to_string(next.status)) + ": " + next.reason);
        break;
      }
      ds_ = controlled_step(ds_, next.newton_iterations, o_.target_newton);  // §4 step 4
      accept(polish(std::move(next)));
    }
    br_.last = cur_;
  }

 protected:
  SigmaContinuation(const Options& o, double cs, double sigma_c) : o_(o), cs_(cs), sigma_c_(sigma_c) {}

  Derived& self() { return static_cast<Derived&>(*this); }
  void stop(BranchEnd e, std::string why) {
    br_.end = e;
    br_.reason = std::move(why);
  }

  // §4 step 2: the second front by a natural step in σ_d below prev_ (there is no secant yet), halved on failure.
  bool second_front() {
    ds_ = o_.initial_step;
    for (;;) {
      if (self().stop_requested()) return false;
      const double target = std::max(prev_.sigma_d - ds_, sigma_c_ + 0.5 * (prev_.sigma_d - sigma_c_));
      cur_ = self().solve_at(target, &prev_);
      if (cur_.status == FrontStatus::converged) break;
      ds_ *= 0.5;
      if (ds_ < o_.min_step) {
        stop(end_of(cur_.status), "no second front below sigma_start: " + cur_.reason);
        br_.last = prev_;
        return false;
      }
    }
    br_.points.push_back(branch_point(cur_));
    self().keep(cur_);
    return true;
  }

  // End detection at the current front: the saddle-node (σ_d − σ_c^d < end_gap·σ_c^d), or the model's own.
  bool reached_end() {
    if (cur_.sigma_d - sigma_c_ < o_.end_gap * sigma_c_) {
      stop(BranchEnd::saddle_node, "");
      return true;
    }
    return self().reached_own_end();
  }

  // Predictor along the secant, corrector with σ_d free (the arclength row), the step halved on failure down to
  // min_step; returns the last attempt (§4 step 7).
  Front predict_and_correct(const Secant& t) {
    ds_ = capped_step(ds_, o_.max_step, t, cur_.sigma_d, sigma_c_);
    Front next;
    for (;;) {
      const double sigma_p = cur_.sigma_d + ds_ * t.t_sigma, c_p = cur_.c + ds_ * t.t_c * cs_;
      const Arclength arc{cur_.sigma_d, cur_.c, t.t_sigma, t.t_c, ds_, cs_};
      next = self().correct(sigma_p, c_p, arc);
      if (next.status == FrontStatus::converged || next.status == FrontStatus::stopped) break;
      ds_ *= 0.5;
      if (ds_ < o_.min_step) break;
    }
    return next;
  }

  // Polish at fixed σ_d (exact Jacobian there; the arclength corrector's σ_d column is a difference quotient),
  // so every branch point is the front the fixed-σ_d solve returns at its σ_d (§4 step 5).
  Front polish(Front next) {
    Front polished = self().solve_at(next.sigma_d, &next);
    if (polished.status == FrontStatus::converged) next = std::move(polished);
    return next;
  }

  // The new front becomes the current one (the secant moves along) and a point of the branch.
  void accept(Front next) {
    prev_ = std::move(cur_);
    cur_ = std::move(next);
    br_.points.push_back(branch_point(cur_));
    self().keep(cur_);
  }

  // The smallest c on a branch followed to an end; false (c_min NaN: not computed) otherwise.
  bool slowest_point_to_c_min(std::size_t& k) {
    if (br_.points.empty() || !followed_to_end(br_.end)) return false;
    const auto slowest = slowest_point(br_.points);
    k = slowest.index;
    br_.c_min = br_.points[k].c;
    br_.sigma_d_at_c_min = br_.points[k].sigma_d;
    br_.c_min_at_end = slowest.at_end;
    return true;
  }

  const Options& o_;
  const double cs_, sigma_c_;
  Branch br_;
  Front prev_, cur_;              ///< the last two fronts of the branch
  double ds_ = 0.0;               ///< the step (natural in σ_d for the second front, then pseudo-arclength)
  double t_sigma_before_ = -1.0;  ///< σ_d component of the previous secant (fold detection)
};

}  // namespace slipfront::continuum::front_solver
