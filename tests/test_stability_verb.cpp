// `slipfront stability` (apps/stability.hpp, docs/cli.md; issue 40 item 5): the growth rates of homogeneous sliding on
// the in-plane strip under the normal-load coupling from a scene. What is checked, on the real binary and
// configs/inplane_stability.toml (H = 4, p_0 = 0.3, 16 rows, v0 = 2: docs/model.md §12.6's strip):
//   - its rates are continuum::leading_growth_rate's with the parameters built here from the scene's keys (μ' = μ(1 − ν)/(2H),
//     ρ' = ρ/H, λ' = 2μ'ν/(1 − 2ν)), exactly, at two kH, in stability.h5 and in growth_rates.csv (17 digits), for the
//     four channels, and its row check's rates on 32 and 64 rows too;
//   - what they say (docs/model.md §12.6, §12.7): re-attachment stable (Re s within round-off), the instantaneous channel's
//     fastest mode not converged in the rows, the regularised one's (L = 0.03, the waveguide mode at kH = 0.25) converged;
//   - /meta (status, git_commit, created_utc) and /config (the resolved scene);
//   - SIGINT: stability.h5 with status interrupted, exit 130, no growth_rates.csv;
//   - refusals before any work, with the key and the reason: an antiplane strip, the chain, no coupling, v0 on the weakening
//     branch, an existing stability.h5 without --force.
#include <catch2/catch.hpp>

#include <signal.h>

#include <chrono>
#include <thread>

#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "continuum/inplane_stability.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using slipfront::testing::TempDir;
using Complex = std::complex<double>;

namespace {

const std::string scene_file = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/inplane_stability.toml";

// The linearisation's parameters of configs/inplane_stability.toml, from its keys (not from the verb's code).
slipfront::continuum::InPlaneStabilityParams scene_params(int rows) {
  const double mu = 300.0, rho = 0.01, nu = 0.3333333333333333, H = 4.0;
  slipfront::continuum::InPlaneStabilityParams p;
  p.height = H;
  p.mu_p = mu * (1.0 - nu) / (2.0 * H);
  p.lambda_p = 2.0 * p.mu_p * nu / (1.0 - 2.0 * nu);
  p.rho_p = rho / H;
  p.alpha = 1.05;
  p.kappa = 8.0;
  p.eta = 0.1;
  p.v0 = 2.0;
  p.p0 = 0.3;
  p.exponent = 1.0;
  p.elements = rows;
  return p;
}

// growth_rates.csv as {channel|kH|kind: s}.
std::map<std::string, Complex> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  REQUIRE(line == "channel,kH,kind,re_s,im_s");
  std::map<std::string, Complex> out;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string channel, kh, kind, re, im;
    std::getline(ss, channel, ',');
    std::getline(ss, kh, ',');
    std::getline(ss, kind, ',');
    std::getline(ss, re, ',');
    std::getline(ss, im, ',');
    out[channel + "|" + kh + "|" + kind] = Complex(std::strtod(re.c_str(), nullptr), std::strtod(im.c_str(), nullptr));
  }
  return out;
}

}  // namespace

TEST_CASE("stability verb: the rates are continuum::leading_growth_rate's, exactly, and say what docs/model.md says",
          "[stability][cli]") {
  const TempDir dir("stability-verb");
  const auto o = slipfront::testing::run(
      {SLIPFRONT_BINARY, "stability", scene_file, "--v0", "2", "--kh", "0.25,2", "--out", (dir.path / "s").string()},
      dir.path);
  INFO(o.out << o.err);
  REQUIRE(o.code == 0);
  const auto f = slipfront::testing::read_h5(dir.path / "s" / "stability.h5");
  CHECK(f.strings.at("/meta@status") == "complete");
  CHECK_FALSE(f.strings.at("/meta@git_commit").empty());
  CHECK(f.strings.at("/meta@created_utc").size() == 20);
  CHECK(f.strings.at("/config@toml").find("load_coupling = \"sigma_yy\"") != std::string::npos);
  CHECK(f.strings.at("/stability@scene_channel") == "reattachment");
  CHECK(f.numbers.at("/stability@rows") == 16.0);
  CHECK(f.numbers.at("/stability@coupling_coefficient") == Approx(1.05 / 17.0 / 0.3).epsilon(1e-14));
  const auto csv = read_csv(dir.path / "s" / "growth_rates.csv");
  REQUIRE(f.datasets.at("/stability/kH") == std::vector<double>{0.25, 2.0});
  struct Channel {
    const char* group;
    const char* label;
    bool coupled, instantaneous;
    double length;
  };
  const double all = std::numeric_limits<double>::max();
  for (const Channel c : {Channel{"uncoupled", "uncoupled", false, false, 0.0},
                          Channel{"reattachment", "reattachment", true, false, 0.0},
                          Channel{"instantaneous", "instantaneous", true, true, 0.0},
                          Channel{"regularised", "instantaneous L=0.03", true, true, 0.03}}) {
    INFO(c.group);
    auto p = scene_params(16);
    p.coupled = c.coupled;
    p.instantaneous = c.instantaneous;
    p.relaxation_length = c.length;
    const double cp = std::sqrt((p.lambda_p + 2.0 * p.mu_p) / p.rho_p), bound = 4.0 * cp / p.height;
    const std::string g = std::string("/stability/") + c.group;
    for (std::size_t a = 0; a < 2; ++a) {
      const double kh = a == 0 ? 0.25 : 2.0;
      const Complex resolved = slipfront::continuum::leading_growth_rate(p, kh / p.height, bound);
      const Complex fastest = slipfront::continuum::leading_growth_rate(p, kh / p.height, all);
      CHECK(f.datasets.at(g + "/resolved_re")[a] == resolved.real());
      CHECK(f.datasets.at(g + "/resolved_im")[a] == resolved.imag());
      CHECK(f.datasets.at(g + "/fastest_re")[a] == fastest.real());
      CHECK(f.datasets.at(g + "/fastest_im")[a] == fastest.imag());
      const std::string key = std::string(c.label) + "|" + (a == 0 ? "0.25" : "2") + "|";
      CHECK(csv.at(key + "theory_resolved") == resolved);
      CHECK(csv.at(key + "theory_max") == fastest);
    }
    // the row check: the fastest mode at the channel's fastest kH on 32 and 64 rows
    const double check_kh = f.numbers.at(g + "@check_kH");
    REQUIRE(f.datasets.at(g + "/check_rows") == std::vector<double>{16, 32, 64});
    for (std::size_t m = 1; m < 3; ++m) {
      auto q = p;
      q.elements = 16 << m;
      CHECK(f.datasets.at(g + "/check_re")[m] == slipfront::continuum::leading_growth_rate(q, check_kh / q.height, all).real());
    }
    std::printf("stability verb, %s: fastest Re s %.6g, %.6g (kH 0.25, 2); at kH %g on 16, 32, 64 rows %.6g %.6g %.6g, "
                "converged %g\n", c.group, f.datasets.at(g + "/fastest_re")[0], f.datasets.at(g + "/fastest_re")[1],
                check_kh, f.datasets.at(g + "/check_re")[0], f.datasets.at(g + "/check_re")[1],
                f.datasets.at(g + "/check_re")[2], f.numbers.at(g + "@converged"));
  }
  // docs/model.md §12.6: re-attachment stable (no Re s above the eigensolver's round-off); the instantaneous channel's
  // fastest mode (kH = 2: 1.69 on 16 rows) moves with the rows; §12.7: regularised at L = 0.03, the waveguide mode at
  // kH = 0.25 grows at ~0.47-0.48 and converges (0.4795, 0.4716, 0.4696 on 16, 32, 64 rows)
  for (std::size_t a = 0; a < 2; ++a)
    CHECK(f.datasets.at("/stability/reattachment/fastest_re")[a] <= f.datasets.at("/stability/reattachment/roundoff")[a]);
  CHECK(f.datasets.at("/stability/instantaneous/fastest_re")[1] > 1.0);
  CHECK(f.numbers.at("/stability/instantaneous@converged") == 0.0);
  CHECK(f.numbers.at("/stability/regularised@check_kH") == 0.25);
  CHECK(f.datasets.at("/stability/regularised/check_re")[2] == Approx(0.4696).epsilon(2e-3));
  CHECK(f.numbers.at("/stability/regularised@converged") == 1.0);
  CHECK(o.out.find("instantaneous: largest Re s") != std::string::npos);
}

TEST_CASE("stability verb: refusals before any work, with the key and the reason", "[stability][cli][hostile]") {
  const TempDir dir("stability-refused");
  struct Case {
    std::vector<std::string> args;
    const char* key;
    const char* reason;
  };
  const std::string src = SLIPFRONT_SOURCE_DIR;
  const Case cases[] = {
      {{src + "/configs/fig1_strip.toml", "--v0", "2"}, "bulk.body", "antiplane"},
      {{src + "/configs/fig1.toml", "--v0", "2"}, "bulk.body", "chain"},
      {{scene_file, "--v0", "2", "--set", "interface.load_coupling=none"}, "interface.load_coupling", "sigma_yy"},
      {{scene_file, "--v0", "0.5"}, "--v0", "strengthening branch v0 > v_m = 1.02064"},
      {{scene_file, "--v0", "1.0206"}, "--v0", "weakening"},
      {{scene_file, "--v0", "2", "--kh", "0.5,-1"}, "--kh", "> 0"},
      {{scene_file, "--v0", "2", "--kh-min", "2", "--kh-max", "1"}, "--kh-min", "kh-min <= kh-max"},
      {{scene_file, "--v0", "2", "--relaxation-length", "0"}, "--relaxation-length", "> 0"},
  };
  int k = 0;
  for (const auto& c : cases) {
    const fs::path out = dir.path / ("o" + std::to_string(k++));
    std::vector<std::string> args = {SLIPFRONT_BINARY, "stability"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"--out", out.string()});
    const auto o = slipfront::testing::run(args, dir.path);
    INFO(c.key << ": " << o.err);
    CHECK(o.code == 2);
    CHECK(o.err.find(c.key) != std::string::npos);
    CHECK(o.err.find(c.reason) != std::string::npos);
    CHECK_FALSE(fs::exists(out));  // nothing written, not even the directory
  }
  // an existing stability.h5 is kept unless --force
  const fs::path out = dir.path / "again";
  const std::vector<std::string> args = {SLIPFRONT_BINARY, "stability", scene_file, "--v0", "2", "--kh", "1",
                                         "--rows", "4", "--out", out.string()};
  REQUIRE(slipfront::testing::run(args, dir.path).code == 0);
  const auto before = fs::last_write_time(out / "stability.h5");
  const auto again = slipfront::testing::run(args, dir.path);
  CHECK(again.code == 2);
  CHECK(again.err.find("already exists (use --force") != std::string::npos);
  CHECK(fs::last_write_time(out / "stability.h5") == before);
  auto forced = args;
  forced.push_back("--force");
  CHECK(slipfront::testing::run(forced, dir.path).code == 0);
}

TEST_CASE("stability verb: SIGINT stops between kH values and writes stability.h5 with status interrupted, no CSV",
          "[stability][cli]") {
  // 10000 kH values on 32 rows: minutes of work; stopped after 1.5 s, it ends within a kH value's solves (~0.1 s).
  const TempDir dir("stability-sigint");
  const fs::path out = dir.path / "s";
  const auto child = slipfront::testing::spawn({SLIPFRONT_BINARY, "stability", scene_file, "--v0", "2", "--points",
                                                "10000", "--rows", "32", "--out", out.string()},
                                               dir.path, dir.path / "out.txt", dir.path / "err.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  REQUIRE(::kill(child.pid, SIGINT) == 0);
  const int code = slipfront::testing::wait_for(child, 60);
  INFO(slipfront::testing::slurp(child.err_path));
  CHECK(code == 130);
  const auto f = slipfront::testing::read_h5(out / "stability.h5");
  CHECK(f.strings.at("/meta@status") == "interrupted");
  CHECK(f.datasets.at("/stability/kH").size() == 10000);
  CHECK(f.datasets.at("/stability/uncoupled/fastest_re").size() < 10000);  // what was computed, no more
  CHECK_FALSE(fs::exists(out / "growth_rates.csv"));
}
