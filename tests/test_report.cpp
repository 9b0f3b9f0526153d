// The report (issue 4): after `slipfront run` (both models), `slipfront study` and
// `slipfront report`, every plot report.md names exists and is a non-empty PNG, and the report holds
// the summary table and the study's fitted rate. Runs the real binary and Debian's /usr/bin/python3.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;

namespace {
int sh(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// The images report.md links, by the heading ("## ...") they appear under.
std::map<std::string, std::vector<std::string>> images_by_heading(const std::string& md) {
  std::map<std::string, std::vector<std::string>> out;
  std::istringstream in(md);
  std::string line, heading;
  const std::regex image(R"(!\[[^\]]*\]\(([^)]+)\))");
  std::smatch m;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) heading = line;
    if (std::regex_search(line, m, image)) out[heading].push_back(m[1].str());
  }
  return out;
}

// A friction-law run (0.01 s) into dir, `points` steady-friction points.
void run_friction_law(const fs::path& dir, int points) {
  const std::string src = SLIPFRONT_SOURCE_DIR;
  REQUIRE(sh(std::string(SLIPFRONT_BINARY) + " run " + src + "/configs/friction_law.toml --out " + dir.string() +
             " -q --force --set drive.points=" + std::to_string(points) + " > /dev/null") == 0);
}

const std::string report_script = std::string(SLIPFRONT_SOURCE_DIR) + "/scripts/report.py";

std::size_t lines_of(const fs::path& p) {
  const std::string text = slipfront::testing::slurp(p);
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

// The first screen (issue 42) of the report of fig1 to t = 60 (first yield, no transient yet), friction_law, the study
// friction_law_N and the c_min(H) data: provenance from the files, the answers in the paper's order with Yes/No and
// their figures, one digest row per limit, the sections in the paper's order, the tables as CSV, no NaN or empty
// bullet.
void first_screen_checks(const fs::path& dir, const std::string& md) {
  CHECK(md.rfind("# slipfront report\n\nCommit ", 0) == 0);
  CHECK(md.find("; computed 20") != std::string::npos);  // the files' created_utc, not the clock
  CHECK(md.find("inputs: 3 of 3 result files complete") != std::string::npos);
  const auto answers = md.find("## Answers to the paper's questions"), digest = md.find("## Limits that must hold: digest"),
             summary = md.find("## Summary");
  REQUIRE(answers != std::string::npos);
  REQUIRE(digest != std::string::npos);
  CHECK(answers < digest);
  CHECK(digest < summary);
  const auto fig1 = md.find("- **Fig. 1: does edge loading"), left = md.find("- **Fig. 2 left:"),
             cmin = md.find("- **Does the minimal steady front speed vary smoothly");
  CHECK(fig1 < left);
  CHECK(left < cmin);
  CHECK(cmin < digest);
  CHECK(md.find("No — the sequence is incomplete (continuum): t* = 25.67, no t^, no x_arrest.", fig1) < left);
  CHECK(md.find("Yes — sigma_ss(v) falls, then rises: its minimum sigma_c^d = 0.21663", left) < cmin);
  CHECK(md.find("([figure](figures/friction_law__results-", left) < cmin);
  CHECK(md.find("Yes — c_min is found at every H = 1 .. 1e+06", cmin) < digest);
  // one digest row per limit, before the full table
  const auto row = md.find("| discrete -> continuum as N -> inf at w = 0 | ");
  CHECK(row > digest);
  CHECK(row < summary);
  CHECK(md.find("| discrete -> continuum as N -> inf at w = 0 | ", row + 1) > md.find("### Limits that must hold"));
  CHECK(md.find("Figures: [Fig. 1](figures/fig1__results-") < summary);
  // the paper's order: the study friction_law_N (Fig. 2 left's convergence) before c_min(H) (the strip)
  CHECK(md.find("## Study `small`") < md.find("## c_min(H) of the strip at fixed material"));
  CHECK(md.find("## Scene `fig1`") < md.find("## Scene `friction_law`"));
  // the full tables as CSV: a header and one line per row of the markdown table
  const auto limits = md.substr(md.find("### Limits that must hold"));
  const std::size_t rows_md = static_cast<std::size_t>(std::count(limits.begin(), limits.begin() + static_cast<long>(limits.find("### Effects")), '\n')) - 7;
  CHECK(lines_of(dir / "summary_limits.csv") == rows_md + 1);
  CHECK(fs::exists(dir / "summary_effects.csv"));
  CHECK(lines_of(dir / "summary_measurements.csv") >= 2);
  CHECK(md.find("= nan") == std::string::npos);
  CHECK(md.find(": \n") == std::string::npos);  // no bullet with an empty definition
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
  // in a directory named as the main job's study, after the c_min(H) data: the sections follow the paper's order
  // (the study before c_min(H)), not the paths' (strip_cmin_height/ before studies/)
  REQUIRE(sh(bin + " study " + study.string() + " --out " + dir.string() + "/studies/friction_law_N -q > /dev/null") == 0);
  fs::create_directories(dir / "strip_cmin_height");
  fs::copy_file(fs::path(src) / "docs" / "data" / "strip_cmin_height.csv", dir / "strip_cmin_height" / "strip_cmin_height.csv");
  REQUIRE(sh(bin + " report " + dir.string() + " > /dev/null") == 0);

  std::ifstream in(dir / "report.md");
  REQUIRE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string md = ss.str();
  CHECK(md.find("| observable | continuum (or the value) | discrete (largest N) | difference | note |") != std::string::npos);
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
  CHECK(n >= 6);  // fig1 fronts + tip, the friction law, the study's error and Fig. 2 left, c_min(H)
  first_screen_checks(dir, md);
  // check_report.py --numbers: each number a page quotes from the run against the run's files, at the precision quoted
  const auto numbers = [&](const std::string& t_star, const std::string& ratio) {
    slipfront::testing::write_text(dir / "results.md",
                                   "# Quoted\n\n| quoted | value | file | expression |\n| --- | --- | --- | --- |\n"
                                   "| fig1 t* | " + t_star + " | `fig1/results.h5` | `f['continuum/events'].attrs['t_star']` |\n"
                                   "| c_min/c_min,1D at the largest H | " + ratio + " | `strip_cmin_height/strip_cmin_height.csv` | "
                                   "`c['c_min'][-1] / c['c_min_1d'][-1]` |\n\nprose | not | a | row\n");
    return slipfront::testing::run({"/usr/bin/python3", src + "/scripts/check_report.py", (dir / "report.md").string(),
                                    "--numbers", (dir / "results.md").string()}, dir);
  };
  const auto right = numbers("25.67", "0.302");
  INFO(right.out << right.err);
  CHECK(right.code == 0);
  CHECK(right.out.find("2 numbers quoted in") != std::string::npos);
  const auto stale = numbers("25.68", "0.302");  // t* = 25.6707: 25.68 is off by more than half its last digit
  CHECK(stale.code == 1);
  CHECK(stale.err.find("'fig1 t*' = 25.68, but fig1/results.h5 gives 25.6707") != std::string::npos);
  CHECK(numbers("25.7", "0.31").err.find("'c_min/c_min,1D at the largest H' = 0.31, but") != std::string::npos);
  // the checker the main job uses agrees
  CHECK(sh("/usr/bin/python3 " + src + "/scripts/check_report.py " + (dir / "report.md").string() + " > /dev/null") == 0);
  // the files are reported in parallel (one worker process per core): one worker and three give this report byte
  // for byte (its sections are joined in a fixed order)
  for (const char* jobs : {"1", "3"}) {
    INFO("SLIPFRONT_REPORT_JOBS=" << jobs);
    REQUIRE(sh(std::string("SLIPFRONT_REPORT_JOBS=") + jobs + " " + bin + " report " + dir.string() + " > /dev/null") == 0);
    CHECK(slipfront::testing::slurp(dir / "report.md") == md);
  }
}

TEST_CASE("report: two runs of one scene in different directories never share figure files", "[report]") {
  // The same scene (friction_law) run twice, into a/fl and b/fl, with 9 and 7 points: before, both wrote
  // figures/friction_law/*.png, so one run's plots appeared under the other's heading. Figures are now in a
  // directory named after each file's path (and a hash of it): two headings, two distinct files, and each
  // heading's figure is its own run's (the two PNGs differ).
  const slipfront::testing::TempDir scratch("report-two");
  const fs::path& dir = scratch.path;
  run_friction_law(dir / "a" / "fl", 9);
  run_friction_law(dir / "b" / "fl", 7);
  REQUIRE(sh(std::string(SLIPFRONT_BINARY) + " report " + dir.string() + " > /dev/null") == 0);
  const std::string md = slipfront::testing::slurp(dir / "report.md");
  const auto by_heading = images_by_heading(md);
  std::vector<std::string> scenes;
  for (const auto& [heading, images] : by_heading)
    if (heading.rfind("## Scene", 0) == 0) scenes.push_back(heading);
  REQUIRE(scenes.size() == 1);  // both headings read "## Scene `friction_law`": one map key, both runs' images
  const auto& images = by_heading.at(scenes[0]);
  REQUIRE(images.size() == 2);
  CHECK(images[0] != images[1]);
  for (const auto& rel : images) {
    INFO(rel);
    CHECK(fs::is_regular_file(dir / rel));
  }
  CHECK(images[0].find("a__fl__results-") != std::string::npos);
  CHECK(images[1].find("b__fl__results-") != std::string::npos);
  CHECK(slipfront::testing::slurp(dir / images[0]) != slipfront::testing::slurp(dir / images[1]));
  // each image under its own section (the first screen's answer links the first one too: "([figure](...))")
  CHECK(md.find("File: `a/fl/results.h5`") < md.find(images[0] + ")\n"));
  CHECK(md.find(images[0] + ")\n") < md.find("File: `b/fl/results.h5`"));
  CHECK(md.find("File: `b/fl/results.h5`") < md.find(images[1] + ")\n"));
}

TEST_CASE("report: non-UTF-8 metadata gives a report with replacement characters, a failed write keeps the previous one",
          "[report]") {
  // A results file whose /meta scene and git_commit and /config toml (the description) hold bytes that are not
  // UTF-8 (h5py hands them over with surrogate escapes): report.md was a 0-byte file (UnicodeEncodeError after
  // opening it). Now the report is written, UTF-8, with U+FFFD for the bad bytes, and check_report.py passes.
  // Then a write that fails (fsync: ENOSPC, as on a full disk) leaves that report.md byte for byte, and no
  // temporary file.
  const slipfront::testing::TempDir scratch("report-utf8");
  const fs::path& dir = scratch.path;
  run_friction_law(dir / "fl", 9);
  const fs::path corrupt = dir / "corrupt.py";
  slipfront::testing::write_text(corrupt, R"(import sys
import h5py
import numpy as np

def put(obj, name, raw):
    if name in obj.attrs:
        del obj.attrs[name]
    obj.attrs.create(name, np.array(raw, dtype=h5py.string_dtype("utf-8")))

with h5py.File(sys.argv[1], "r+") as f:
    put(f["meta"], "git_commit", b"fe0f37b-\xff\xfe")
    put(f["meta"], "scene", b"friction_\xe9law")
    toml = f["config"].attrs["toml"]
    toml = toml.encode("utf-8", "surrogateescape") if isinstance(toml, str) else toml
    put(f["config"], "toml", toml.replace(b'description = "', b'description = "caf\xe9 \xff '))
)");
  REQUIRE(sh("/usr/bin/python3 " + corrupt.string() + " " + (dir / "fl" / "results.h5").string()) == 0);
  REQUIRE(sh(std::string(SLIPFRONT_BINARY) + " report " + dir.string() + " > /dev/null 2>&1") == 0);
  const std::string md = slipfront::testing::slurp(dir / "report.md");
  CHECK(md.size() > 200);
  CHECK(md.find("caf\xEF\xBF\xBD \xEF\xBF\xBD Steady friction law") != std::string::npos);  // U+FFFD
  CHECK(sh("/usr/bin/python3 " + std::string(SLIPFRONT_SOURCE_DIR) + "/scripts/check_report.py " +
           (dir / "report.md").string() + " > /dev/null") == 0);

  const std::string inject = "import errno, os, sys\n"
                             "sys.path.insert(0, os.path.dirname(sys.argv[1]))\n"
                             "import report\n"
                             "def full(fd):\n"
                             "    raise OSError(errno.ENOSPC, 'No space left on device')\n"
                             "os.fsync = full\n"
                             "sys.exit(report.main([sys.argv[2]]))\n";
  const auto failed = slipfront::testing::run({"/usr/bin/python3", "-c", inject, report_script, dir.string()}, dir);
  INFO(failed.err);
  CHECK(failed.code != 0);
  CHECK(failed.err.find("No space left on device") != std::string::npos);
  CHECK(slipfront::testing::slurp(dir / "report.md") == md);
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename().string().rfind(".report.md.", 0) != 0);
}

TEST_CASE("report: the strip's body pictures and the events-vs-H figure, and none for runs without bulk snapshots",
          "[report][strip]") {
  // A small fig1 strip with bulk snapshots (H = 4, every 5 time units: its t^ ~ 77 bracketed), the same strip
  // without them, the 1D fig1, and a tiny strip_height study (3 heights and the chain). The report pictures the
  // body of the first only (u, tau_xz, tau_yz, one figure per model), plots the study's events against H/l_e, and
  // check_report.py passes.
  const std::string bin = SLIPFRONT_BINARY, src = SLIPFRONT_SOURCE_DIR;
  const slipfront::testing::TempDir scratch("report-strip");
  const fs::path& dir = scratch.path;
  const std::string small = " -q --force --set bulk.length=60 --set grid.dx=1 --set time.dt=0.001 --set time.t_end=90"
                            " --set discrete.contacts_per_site=1000 --set output.snapshot_dt=1";
  REQUIRE(sh(bin + " run " + src + "/configs/fig1_strip.toml --out " + (dir / "strip_bulk").string() + small +
             " --set bulk.height=4 --set grid.dy=1 --set output.bulk_dt=5 --set output.bulk_stride=2 > /dev/null") == 0);
  REQUIRE(sh(bin + " run " + src + "/configs/fig1_strip.toml --out " + (dir / "strip_plain").string() + small +
             " --set bulk.height=4 --set grid.dy=1 --set output.bulk_dt=0 > /dev/null") == 0);
  REQUIRE(sh(bin + " run " + src + "/configs/fig1.toml --out " + (dir / "chain").string() + small + " > /dev/null") == 0);
  const fs::path study = dir / "strip_height.toml";
  std::ofstream(study) << "study = \"tiny_strip_height\"\nkind = \"strip_height\"\nscene = \"" << src
                       << "/configs/fig1_strip.toml\"\n"
                          "set = [\"bulk.length=60\", \"grid.dx=1\", \"time.dt=0.001\", \"time.t_end=90\",\n"
                          "       \"discrete.contacts_per_site=1000\", \"output.snapshot_dt=0\", \"output.bulk_dt=0\"]\n"
                          "[[group]]\nname = \"fine\"\nvary = { \"bulk.height\" = [0.25, 2.0], \"grid.dy\" = [0.25] }\n"
                          "[[group]]\nname = \"coarse\"\nvary = { \"bulk.height\" = [17.0], \"grid.dy\" = [1.0] }\n"
                          "[[group]]\nname = \"chain\"\nvary = { \"bulk.height\" = [0.0], \"grid.dy\" = [0.0] }\n";
  REQUIRE(sh(bin + " study " + study.string() + " --out " + (dir / "studies" / "tiny").string() + " -q > /dev/null") == 0);
  REQUIRE(sh(bin + " report " + dir.string() + " > /dev/null") == 0);

  const std::string md = slipfront::testing::slurp(dir / "report.md");
  std::vector<std::string> fields, plain, chain, vs_h;
  const std::regex image(R"(!\[[^\]]*\]\(([^)]+)\))");
  for (auto it = std::sregex_iterator(md.begin(), md.end(), image); it != std::sregex_iterator(); ++it) {
    const std::string rel = (*it)[1].str();
    INFO(rel);
    CHECK(fs::file_size(dir / rel) > 1000);
    if (rel.find("_strip_fields_") != std::string::npos) fields.push_back(rel);
    if (rel.find("strip_plain__results-") != std::string::npos) plain.push_back(rel);
    if (rel.find("chain__results-") != std::string::npos) chain.push_back(rel);
    if (rel.find("_events_vs_H.png") != std::string::npos) vs_h.push_back(rel);
  }
  REQUIRE(fields.size() == 2);  // one per model, both of the run with bulk snapshots
  for (const auto& f : fields) CHECK(f.find("strip_bulk__results-") != std::string::npos);
  CHECK(fields[0].find("fig1_strip_strip_fields_continuum.png") != std::string::npos);
  CHECK(fields[1].find("fig1_strip_strip_fields_discrete.png") != std::string::npos);
  CHECK(md.find("### The strip's body") != std::string::npos);
  CHECK(plain.size() >= 2);  // its fronts and tip plots, and no body pictures (counted above)
  CHECK(chain.size() >= 2);
  REQUIRE(vs_h.size() == 1);
  CHECK(vs_h[0].find("tiny_strip_height") != std::string::npos);
  CHECK(md.find("## Study `tiny_strip_height` (strip_height)") < md.find(vs_h[0]));
  // summary rows: H -> 0 is a limit (with its verdict), the largest H an effect of the strip height
  const std::string effects_part = md.substr(md.find("### Effects of a parameter"));
  CHECK(md.find("| strip -> 1D chain as H -> 0 (both models) | tiny_strip_height: t_star, 1D chain -> H = 0.25") <
        md.find("### Effects of a parameter"));
  CHECK(effects_part.find("| strip height H | tiny_strip_height: t_star, 1D chain -> H = 17") != std::string::npos);
  CHECK(sh("/usr/bin/python3 " + src + "/scripts/check_report.py " + (dir / "report.md").string() + " > /dev/null") == 0);
}

TEST_CASE("report: the c_min(H) figure and its summary row come from the strip_cmin_height CSV", "[report][strip]") {
  // The committed c_min(H) data (docs/data/strip_cmin_height.csv, H = 1 .. 1e6) as out/.../strip_cmin_height.csv:
  // the report draws c_min vs H (with the local exponent) and one summary row whose numbers are the data's (the 1D
  // regime within 1 % up to H = 3162, the exponent below 0.49 from H/l = 3.33, eps vs eps_BM at H = 1e6). Then the
  // data changed (the 1D c_min 3 % higher from H = 1000 on, the last H dropped): the row follows. A CSV with a header
  // only gives no figure and the report still succeeds.
  const std::string src = SLIPFRONT_SOURCE_DIR;
  const slipfront::testing::TempDir scratch("report-cmin");
  const fs::path& dir = scratch.path;
  const fs::path csv = dir / "cmin" / "strip_cmin_height.csv";
  fs::create_directories(csv.parent_path());
  fs::copy_file(fs::path(src) / "docs" / "data" / "strip_cmin_height.csv", csv);
  const auto report = [&] {
    REQUIRE(sh(std::string(SLIPFRONT_BINARY) + " report " + dir.string() + " > /dev/null") == 0);
    return slipfront::testing::slurp(dir / "report.md");
  };
  const auto figures = [&](const std::string& md) {
    std::vector<std::string> out;
    const std::regex image(R"(!\[[^\]]*\]\(([^)]+_cmin_vs_H\.png)\))");
    for (auto it = std::sregex_iterator(md.begin(), md.end(), image); it != std::sregex_iterator(); ++it) {
      out.push_back((*it)[1].str());
      CHECK(fs::file_size(dir / out.back()) > 10000);
    }
    return out;
  };
  const std::string md = report();
  REQUIRE(figures(md).size() == 1);
  CHECK(md.find("## c_min(H) of the strip at fixed material") < md.find(figures(md)[0] + ")\n"));
  CHECK(md.find("([figure](" + figures(md)[0] + "))") < md.find("## Limits that must hold: digest"));  // its answer
  const std::string row = "| c_min(H) of the strip, H = 1 .. 1e+06: does the 1D c_min hold? | 1D c_min holds (within 1%) "
                          "up to H = 3162 (H/l = 10.5); exponent leaves 1/2 (< 0.49: 0.488) on H/l = 3.33 .. 10.5";
  CHECK(md.find(row) != std::string::npos);
  CHECK(md.find("at H = 1e+06 (H/l_kappa = 43.8): eps = 0.541 vs eps_BM = 0.466 (gap +0.075; c_min = 1.27 x BM), "
                "c_min/c_min,1D = 0.302") != std::string::npos);
  // the same numbers answer the paper's 2D question at the top of the summary, before the three tables
  const auto answer = md.find("### The paper's questions");
  REQUIRE(answer != std::string::npos);
  CHECK(answer < md.find("### Limits that must hold"));
  CHECK(md.find("- **Does the minimal steady front speed vary smoothly from 1D to 2D as H grows?** c_min(H) at fixed "
                "strip material, H = 1 .. 1e+06: 1D c_min holds (within 1%) up to H = 3162 (H/l = 10.5)") > answer);
  CHECK(sh("/usr/bin/python3 " + src + "/scripts/check_report.py " + (dir / "report.md").string() + " > /dev/null") == 0);

  // the data changed: the row's numbers change with it
  const fs::path edit = dir / "edit.py";
  slipfront::testing::write_text(edit, R"(import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
names = list(rows[0].keys())
rows = [r for r in rows if float(r["H"]) < 5e5]
for r in rows:
    if float(r["H"]) >= 1000:
        r["c_min_1d"] = repr(1.03 * float(r["c_min_1d"]))
with open(sys.argv[1], "w", newline="") as f:
    w = csv.DictWriter(f, names)
    w.writeheader()
    w.writerows(rows)
)");
  REQUIRE(sh("/usr/bin/python3 " + edit.string() + " " + csv.string()) == 0);
  const std::string changed = report();
  CHECK(figures(changed).size() == 1);
  CHECK(changed.find(row) == std::string::npos);
  CHECK(changed.find("| c_min(H) of the strip, H = 1 .. 3.162e+05: does the 1D c_min hold? | 1D c_min holds (within "
                     "1%) up to H = 316.2 (H/l = 1.05)") != std::string::npos);
  CHECK(changed.find("at H = 3.162e+05 (H/l_kappa = 13.8): eps = 0.476 vs eps_BM = 0.377") != std::string::npos);

  // no usable row: no figure, no row, the report is still written
  slipfront::testing::write_text(csv, "H,H_over_l,H_over_l_kappa,c_min,c_min_over_s,c_min_over_cs,c_min_1d\n");
  const std::string empty = report();
  CHECK(figures(empty).empty());
  CHECK(empty.find("| c_min(H) of the strip") == std::string::npos);
  CHECK(empty.find("### The paper's questions") == std::string::npos);  // no numbers, no answer
}

namespace {
// The summary's three parts of report.md: the limits table, the effects table, the rest.
struct Summary {
  std::string limits, effects;
};
Summary summary_of(const std::string& md) {
  const auto a = md.find("### Limits that must hold"), b = md.find("### Effects of a parameter"),
             c = md.find("### Measurements");
  REQUIRE(a != std::string::npos);
  REQUIRE(b != std::string::npos);
  REQUIRE(c != std::string::npos);
  REQUIRE(a < b);
  REQUIRE(b < c);
  return {md.substr(a, b - a), md.substr(b, c - b)};
}
// The table rows (lines starting with "| ") of a part that name `file`.
std::vector<std::string> rows_naming(const std::string& part, const std::string& file) {
  std::vector<std::string> out;
  std::istringstream in(part);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("| ", 0) == 0 && line.find("`" + file + "`") != std::string::npos) out.push_back(line);
  return out;
}
}  // namespace

TEST_CASE("report: a disordered scene is tested against mean_field when its file has it, else its differences are effects",
          "[report]") {
  // contacts_disorder (w = 0.2, agent N = 1000, a small chain to t = 40: first yield and the slow front) twice: with
  // mean_field (the scene's models) and without it. With it, the discrete model's events and the contact statistics are
  // rows of "Limits that must hold" tested against mean_field (reference column, verdict), and mean_field against the
  // continuum is an effect of w. Without it, the same differences against the continuum are effects only: no limit row
  // names that file. check_report.py, which reads the files, passes.
  const std::string bin = SLIPFRONT_BINARY, src = SLIPFRONT_SOURCE_DIR;
  const slipfront::testing::TempDir scratch("report-disorder");
  const fs::path& dir = scratch.path;
  const std::string small = " -q --force --set bulk.length=60 --set grid.dx=1 --set time.t_end=40"
                            " --set discrete.contacts_per_site=1000 --set output.contact_snapshot_dt=2";
  REQUIRE(sh(bin + " run " + src + "/configs/contacts_disorder.toml --out " + (dir / "with").string() + small +
             " > /dev/null") == 0);
  REQUIRE(sh(bin + " run " + src + "/configs/contacts_disorder.toml --out " + (dir / "without").string() + small +
             " --set 'models=[\"continuum\",\"discrete\"]' > /dev/null") == 0);
  REQUIRE(sh(bin + " report " + dir.string() + " > /dev/null") == 0);
  const std::string md = slipfront::testing::slurp(dir / "report.md");
  const Summary sum = summary_of(md);

  const auto with_limits = rows_naming(sum.limits, "with/results.h5");
  REQUIRE(with_limits.size() >= 2);  // t_star and at least one contact-statistics row
  bool event = false, contacts = false;
  for (const auto& r : with_limits) {
    INFO(r);
    CHECK(r.find("| mean_field |") != std::string::npos);  // the reference column
    CHECK((r.find("| pass |") != std::string::npos || r.find("| FAIL |") != std::string::npos));
    CHECK(r.find("| 0.2 |") != std::string::npos);
    if (r.find("discrete -> mean_field as N -> inf at w = 0.2 | contacts_disorder: t_star") != std::string::npos) event = true;
    if (r.find("renewal prediction from mean_field at w = 0.2") != std::string::npos) contacts = true;
  }
  CHECK(event);
  CHECK(contacts);
  const auto with_effects = rows_naming(sum.effects, "with/results.h5");
  CHECK(std::any_of(with_effects.begin(), with_effects.end(), [](const std::string& r) {
    return r.find("mean_field: N -> inf at w; continuum: w = 0") != std::string::npos &&
           r.find("contacts_disorder: t_star") != std::string::npos;
  }));

  CHECK(rows_naming(sum.limits, "without/results.h5").empty());  // no verdict against the continuum at w > 0
  const auto without_effects = rows_naming(sum.effects, "without/results.h5");
  bool t_star = false, lifetimes = false;
  for (const auto& r : without_effects) {
    INFO(r);
    CHECK(r.find("| pass |") == std::string::npos);
    CHECK(r.find("| FAIL |") == std::string::npos);
    if (r.find("contacts_disorder: t_star (discrete N=1000) | continuum 25.6") != std::string::npos) t_star = true;
    if (r.find("contact lifetimes, slow front") != std::string::npos &&
        r.find("agent vs the continuum's prediction") != std::string::npos)
      lifetimes = true;
  }
  CHECK(t_star);
  CHECK(lifetimes);
  const auto check = slipfront::testing::run({"/usr/bin/python3", src + "/scripts/check_report.py", (dir / "report.md").string()}, dir);
  INFO(check.out + check.err);
  CHECK(check.code == 0);
  CHECK(check.out.find("verdict rows read against their files; 0 errors") != std::string::npos);
}

TEST_CASE("report: check_report.py rejects a verdict row testing a disordered discrete model against the continuum",
          "[report]") {
  // The report of the case above, edited: (1) a limits row with a verdict for the file without mean_field, tested
  // against the continuum at w = 0.2 (what the summary used to show); (2) the row of the file with mean_field claiming
  // the continuum as its reference. check_report.py reads the files (w from /config, the reference from /compare) and
  // rejects both; the unedited report passes.
  const std::string bin = SLIPFRONT_BINARY, src = SLIPFRONT_SOURCE_DIR;
  const slipfront::testing::TempDir scratch("report-reject");
  const fs::path& dir = scratch.path;
  const std::string small = " -q --force --set bulk.length=60 --set grid.dx=1 --set time.t_end=40"
                            " --set discrete.contacts_per_site=1000 --set discrete.representation=count"
                            " --set discrete.contact_statistics=false";
  REQUIRE(sh(bin + " run " + src + "/configs/contacts_disorder.toml --out " + (dir / "with").string() + small +
             " > /dev/null") == 0);
  REQUIRE(sh(bin + " run " + src + "/configs/contacts_disorder.toml --out " + (dir / "without").string() + small +
             " --set 'models=[\"continuum\",\"discrete\"]' > /dev/null") == 0);
  REQUIRE(sh(bin + " report " + dir.string() + " > /dev/null") == 0);
  const std::string md = slipfront::testing::slurp(dir / "report.md");
  const auto check = [&](const std::string& text) {
    slipfront::testing::write_text(dir / "edited.md", text);
    return slipfront::testing::run({"/usr/bin/python3", src + "/scripts/check_report.py", (dir / "edited.md").string()}, dir);
  };
  CHECK(check(md).code == 0);

  const auto rows = rows_naming(summary_of(md).limits, "with/results.h5");
  REQUIRE(!rows.empty());
  const std::string row = rows[0];
  const auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const auto k = s.find(from);
    REQUIRE(k != std::string::npos);
    return s.replace(k, from.size(), to);
  };
  const std::string as_continuum = replace(row, "| mean_field |", "| continuum |");
  // (1) the file without mean_field, tested against the continuum
  const std::string planted = replace(replace(as_continuum, "`with/results.h5`", "`without/results.h5`"),
                                      "discrete -> mean_field", "discrete -> continuum");
  const auto one = check(replace(md, row + "\n", row + "\n" + planted + "\n"));
  INFO(one.err);
  CHECK(one.code == 1);
  CHECK(one.err.find("against the continuum, a limit it is not supposed to reach") != std::string::npos);
  CHECK(one.err.find("without/results.h5") != std::string::npos);
  // (2) the file with mean_field, its row claiming the continuum
  const auto two = check(replace(md, row, as_continuum));
  INFO(two.err);
  CHECK(two.code == 1);
  CHECK(two.err.find("compared the discrete model with mean_field") != std::string::npos);
  // the same planted row without a verdict (n/a) is not a test: accepted
  CHECK(check(replace(md, row + "\n", row + "\n" + replace(planted, planted.find("| pass |") != std::string::npos ? "| pass |" : "| FAIL |", "| n/a |") + "\n")).code == 0);
}

TEST_CASE("report: an empty or truncated study.h5 or fronts.h5 is listed as unreadable, the rest of the report written "
          "(issue 36)",
          "[report]") {
  // Was: an h5py traceback naming no file, exit 1, no report: one bad file blocked the whole report (a bad
  // results.h5 was already listed and skipped). Now each bad file is listed with its path and the reason.
  const slipfront::testing::TempDir scratch("report-unreadable");
  const fs::path& dir = scratch.path;
  run_friction_law(dir / "fl", 9);
  const std::string src = SLIPFRONT_SOURCE_DIR;
  REQUIRE(sh(std::string(SLIPFRONT_BINARY) + " fronts " + src + "/configs/homogeneous_front.toml --out " +
             (dir / "fronts").string() + " > /dev/null") == 0);
  const std::string whole = slipfront::testing::slurp(dir / "fronts" / "fronts.h5");
  REQUIRE(whole.size() > 8192);
  const std::map<std::string, std::string> bad = {
      {"empty_study/study.h5", ""},
      {"truncated_study/study.h5", whole.substr(0, 4096)},
      {"not_a_study/study.h5", slipfront::testing::slurp(dir / "fl" / "results.h5")},  // HDF5 without /study
      {"empty_fronts/fronts.h5", ""},
      {"truncated_fronts/fronts.h5", whole.substr(0, whole.size() / 2)},
  };
  for (const auto& [name, bytes] : bad) {
    fs::create_directories((dir / name).parent_path());
    slipfront::testing::write_text(dir / name, bytes);
  }
  const auto r = slipfront::testing::run({SLIPFRONT_BINARY, "report", dir.string()}, dir);
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string md = slipfront::testing::slurp(dir / "report.md");
  CHECK(md.find("## Scene `friction_law`") != std::string::npos);  // the rest of the report
  CHECK(md.find("## Steady fronts `homogeneous_front`") != std::string::npos);
  for (const auto& [name, bytes] : bad) {
    INFO(name);
    const std::string line = "- could not read " + (dir / name).string() + ": ";
    const std::size_t at = md.find(line);
    REQUIRE(at != std::string::npos);
    const std::string why = md.substr(at + line.size(), md.find('\n', at) - at - line.size());
    CHECK(why.size() > 5);  // a reason, e.g. "Unable to open file (file signature not found)"
  }
  CHECK(md.find("not_a_study/study.h5: Unable to open object (object 'study' doesn't exist)") != std::string::npos);
}

TEST_CASE("report: strip_cmin_height's rows show c_min with its estimate, the mesh and the NOT met flags",
          "[report][strip]") {
  // Issue 36 item 1: every c_min the report prints carries its estimate, and a height whose paths.rtol was not met
  // (rtol_met = 0 in the CSV) is flagged in the table and counted in the summary row. A CSV of three heights (the
  // shipped study's numbers at H = 1, 1000, 1e4 with the meshes chosen by rtol 1e-3; H = 1e4 stopped at the mesh
  // limit). Fails if an estimate, the mesh or the flag is missing.
  const slipfront::testing::TempDir scratch("report-cmin-errors");
  const fs::path& dir = scratch.path;
  const fs::path csv = dir / "cmin" / "strip_cmin_height.csv";
  fs::create_directories(csv.parent_path());
  slipfront::testing::write_text(csv,
                                 "H,H_over_l,H_over_l_kappa,c_min,c_min_over_s,c_min_over_cs,c_min_1d,ratio_to_1d,"
                                 "local_exponent,rows,intervals,c_min_error,rtol_met\n"
                                 "1,0.00333333,4.375e-05,11.305316,0.00376844,2.06e-05,11.30508793,1.00002,0.5,8,300,6.32e-07,1\n"
                                 "1000,3.33333,0.04375,360.60584,0.120202,0.000658,360.3,1.00085,0.46,8,300,0.0185,1\n"
                                 "10000,33.3333,0.4375,1042.0988,0.347366,0.0019,1140.0,0.914,nan,32,300,1.12,0\n");
  REQUIRE(sh(std::string(SLIPFRONT_BINARY) + " report " + dir.string() + " > /dev/null") == 0);
  const std::string md = slipfront::testing::slurp(dir / "report.md");
  INFO(md);
  CHECK(md.find("| 1 | 11.305316 ± 6.3e-07 | 5.6e-06 % | 8 × 300 | met |") != std::string::npos);
  CHECK(md.find("| 1000 | 360.60584 ± 0.018 | 0.0051 % | 8 × 300 | met |") != std::string::npos);
  CHECK(md.find("| 10000 | 1042.0988 ± 1.1 | 0.11 % | 32 × 300 | **NOT met** |") != std::string::npos);
  CHECK(md.find("**1 of 3 heights NOT met** their rtol (H = 1e+04)") != std::string::npos);
  CHECK(md.find("rtol NOT met at 1 of 3 heights (H = 1e+04)") != std::string::npos);
}

TEST_CASE("report: contact aging's limits are verdict rows, and aging and a load profile against fig1 are effects",
          "[report][aging]") {
  // friction_law_aging (9 rates, agent N = 1000), slide_hold_slide (holds 1, 3, 10, 30; agent N = 1000), fig1 and
  // fig1_load_profile (continuum, to t = 40: first yield) in one tree. The report tests the ensemble against the
  // age-structured mean field (the sweep's minimum, the peaks' ln t_h slope) and the closure's steady offset against the
  // derived one (docs/model.md §11.4), draws <scene>_peaks.png, and lists the load profile's t* against fig1's as an
  // effect; check_report.py, which reads the files, passes.
  const std::string bin = SLIPFRONT_BINARY, src = SLIPFRONT_SOURCE_DIR;
  const slipfront::testing::TempDir scratch("report-aging");
  const fs::path& dir = scratch.path;
  const std::string n1000 = " -q --force --set discrete.contacts_per_site=1000";
  REQUIRE(sh(bin + " run " + src + "/configs/friction_law_aging.toml --out " + (dir / "friction_law_aging").string() +
             n1000 + " --set drive.points=9 > /dev/null") == 0);
  REQUIRE(sh(bin + " run " + src + "/configs/slide_hold_slide.toml --out " + (dir / "slide_hold_slide").string() + n1000 +
             " --set time.t_end=144 --set 'drive.v=[1,0,1,0,1,0,1,0,1]' --set 'drive.switch_times=[0,20,21,41,44,64,74,94,124]'"
             " > /dev/null") == 0);
  for (const std::string scene : {"fig1", "fig1_load_profile"})
    REQUIRE(sh(bin + " run " + src + "/configs/" + scene + ".toml --out " + (dir / scene).string() +
               " -q --force --set time.t_end=40 --set 'models=[\"continuum\"]' > /dev/null") == 0);
  REQUIRE(sh(bin + " report " + dir.string() + " > /dev/null") == 0);
  const std::string md = slipfront::testing::slurp(dir / "report.md");
  const Summary sum = summary_of(md);

  const auto closure = rows_naming(sum.limits, "friction_law_aging/results.h5");
  CHECK(std::any_of(closure.begin(), closure.end(), [](const std::string& r) {
    return r.find("closure -> age-structured balance: the steady offset") != std::string::npos &&
           r.find("| mean_field |") != std::string::npos && r.find("| pass |") != std::string::npos;
  }));
  CHECK(std::any_of(closure.begin(), closure.end(), [](const std::string& r) {
    return r.find("discrete -> mean_field as N -> inf at w = 0 | friction_law_aging: sigma_c^d (closed form with aging") !=
           std::string::npos;
  }));
  const auto peaks = rows_naming(sum.limits, "slide_hold_slide/results.h5");
  CHECK(std::any_of(peaks.begin(), peaks.end(), [](const std::string& r) {
    return r.find("static peak slope d peak / d ln t_h") != std::string::npos &&
           (r.find("| pass |") != std::string::npos || r.find("| FAIL |") != std::string::npos);
  }));
  CHECK(md.find("slide_hold_slide: the one-variable closure's static peaks against mean_field's") != std::string::npos);
  CHECK(md.find("slide_hold_slide_peaks.png") != std::string::npos);
  const auto load = rows_naming(sum.effects, "fig1_load_profile/results.h5");
  CHECK(std::any_of(load.begin(), load.end(), [](const std::string& r) {
    return r.find("normal-load profile") != std::string::npos && r.find("fig1_load_profile: t_star (continuum)") != std::string::npos &&
           r.find("fig1 continuum 25.6") != std::string::npos;
  }));
  CHECK(rows_naming(sum.limits, "fig1_load_profile/results.h5").empty());  // an effect, never a verdict
  const auto check = slipfront::testing::run({"/usr/bin/python3", src + "/scripts/check_report.py", (dir / "report.md").string()}, dir);
  INFO(check.out + check.err);
  CHECK(check.code == 0);
}
