// The report (issue 4): after `slipfront run` (both models), `slipfront study` and
// `slipfront report`, every plot report.md names exists and is a non-empty PNG, and the report holds
// the summary table and the study's fitted rate. Runs the real binary and Debian's /usr/bin/python3.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "scenes.hpp"

namespace fs = std::filesystem;

namespace {
int sh(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
}  // namespace

TEST_CASE("report: every plot named in report.md exists and is a non-empty PNG", "[report]") {
  const std::string bin = SLIPFRONT_BINARY, src = SLIPFRONT_SOURCE_DIR;
  const slipfront::testing::TempDir scratch("report");
  const fs::path& dir = scratch.path;
  const std::string q = " -q --force ";
  REQUIRE(sh(bin + " run " + src + "/configs/fig1.toml --out " + dir.string() + "/fig1" + q +
             "--set time.t_end=60 --set bulk.length=100 --set grid.dx=1 --set discrete.contacts_per_site=1000"
             " > /dev/null") == 0);
  REQUIRE(sh(bin + " run " + src + "/configs/friction_law.toml --out " + dir.string() + "/friction_law" + q +
             "--set drive.points=9 > /dev/null") == 0);
  // a small study: its own file, based on the friction_law scene
  const fs::path study = dir / "study.toml";
  std::ofstream(study) << "study = \"small\"\nkind = \"friction_law\"\nscene = \"" << src
                       << "/configs/friction_law.toml\"\nset = [\"drive.points=5\", \"time.steps=500\"]\n"
                          "seeds = 2\n[vary]\n\"discrete.contacts_per_site\" = [100, 1000, 10000]\n";
  REQUIRE(sh(bin + " study " + study.string() + " --out " + dir.string() + "/studies/small -q > /dev/null") == 0);
  REQUIRE(sh(bin + " report " + dir.string() + " > /dev/null") == 0);

  std::ifstream in(dir / "report.md");
  REQUIRE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string md = ss.str();
  CHECK(md.find("| observable | continuum |") != std::string::npos);
  CHECK(md.find("friction_law_random_exponent") != std::string::npos);
  const std::regex image(R"(!\[[^\]]*\]\(([^)]+)\))");
  int n = 0;
  for (auto it = std::sregex_iterator(md.begin(), md.end(), image); it != std::sregex_iterator(); ++it, ++n) {
    const fs::path p = dir / (*it)[1].str();
    INFO(p.string());
    REQUIRE(fs::is_regular_file(p));
    std::ifstream png(p, std::ios::binary);
    char magic[8] = {};
    png.read(magic, 8);
    CHECK(std::string(magic, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
    CHECK(fs::file_size(p) > 1000);
  }
  CHECK(n >= 5);  // fig1 fronts + tip, the friction law, the study's error and Fig. 2 left
  // the checker the main job uses agrees
  CHECK(sh("/usr/bin/python3 " + src + "/scripts/check_report.py " + (dir / "report.md").string() + " > /dev/null") == 0);
}
