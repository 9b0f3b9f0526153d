// Compile-time check of core::LawHooks (issue 17): built with -fsyntax-only by ctest, once per case
// (tests/CMakeLists.txt: compile_law_hooks_*). LAW_HOOKS_CASE selects the law:
//   0  a well-formed law with the age hooks declared: must compile (the control)
//   1  ages declared, but mean_age misspelt as mean_ages: must fail with the LawHooks::ages message
//   2  the age hooks present but not declared: must fail with the same message
//   3  no `hooks` at all: not an interface law, must fail
#include <span>

#include "core/law.hpp"
#include "core/stepper.hpp"

namespace {

template <bool Declare, bool Misspell, bool WithHooks = true>
class TinyLaw {
 public:
  static constexpr slipfront::core::LawHooks hooks{.ages = Declare};
  std::size_t size() const { return 1; }
  const slipfront::core::InterfaceParams& params() const { return p_; }
  std::span<const double> contact_area() const { return {&a_, 1}; }
  std::span<const double> sigma_bar() const { return {&s_, 1}; }
  void set_site(std::size_t, double a, double s) { a_ = a, s_ = s; }
  slipfront::core::LawStepInfo advance(double, std::span<const double>) { return {}; }
  auto linearisation(double) const {
    return [](std::size_t, double, double& c0, double& c1) { c0 = c1 = 0.0; };
  }
  void track_ages(bool) {}
  bool tracks_ages() const { return false; }
  void mean_age(std::span<double>) const
    requires(!Misspell)
  {}
  void mean_ages(std::span<double>) const
    requires(Misspell)
  {}

 private:
  slipfront::core::InterfaceParams p_{};
  double a_ = 1.0, s_ = 0.0;
};

class NoHooksLaw {
 public:
  std::size_t size() const { return 1; }
  const slipfront::core::InterfaceParams& params() const { return p_; }
  std::span<const double> contact_area() const { return {&a_, 1}; }
  std::span<const double> sigma_bar() const { return {&a_, 1}; }
  void set_site(std::size_t, double, double) {}
  slipfront::core::LawStepInfo advance(double, std::span<const double>) { return {}; }
  auto linearisation(double) const {
    return [](std::size_t, double, double& c0, double& c1) { c0 = c1 = 0.0; };
  }

 private:
  slipfront::core::InterfaceParams p_{};
  double a_ = 1.0;
};

}  // namespace

#if LAW_HOOKS_CASE == 0
static_assert(slipfront::core::InterfaceLaw<TinyLaw<true, false>>);
#elif LAW_HOOKS_CASE == 1
static_assert(slipfront::core::InterfaceLaw<TinyLaw<true, true>>);
#elif LAW_HOOKS_CASE == 2
static_assert(slipfront::core::InterfaceLaw<TinyLaw<false, false>>);
#else
template class slipfront::core::ExplicitSimulation<NoHooksLaw>;
#endif
