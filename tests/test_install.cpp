// `cmake --install` (issue 9 item 7): the installed program runs a scene, a study and the report
// from any working directory, with its scripts found relative to itself (<prefix>/share/slipfront),
// no shell involved (directory names with a quote and a space), and the MPI engine found in
// <prefix>/lib/slipfront when mpirun is there.
#include <catch2/catch.hpp>

#include <fstream>
#include <string>
#include <vector>

#include "apps/build_info.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using namespace slipfront::testing;

TEST_CASE("install: the installed slipfront runs a scene, a study and the report from another directory", "[install]") {
  const TempDir root("install");
  const fs::path prefix = root.path / "pre fix's";
  const fs::path work = root.path / "it's a dir";
  fs::create_directories(work);

  const Output inst = run({SLIPFRONT_CMAKE_COMMAND, "--install", SLIPFRONT_BUILD_DIR, "--prefix", prefix.string()},
                          root.path);
  INFO(inst.out << inst.err);
  REQUIRE(inst.code == 0);
  const fs::path bin = prefix / "bin" / "slipfront";
  const fs::path share = prefix / "share" / "slipfront";
  REQUIRE(fs::is_regular_file(bin));
  for (const char* f : {"report.py", "plot.py", "check_report.py", "examples/fig1.toml", "examples/friction_law.toml",
                        "examples/studies/friction_law_N.toml", "examples/hard"})
    CHECK(fs::exists(share / f));
  const fs::path engine =
      (prefix / "bin" / app::build_info::lib_dir_from_bin / app::build_info::mpi_engine_name).lexically_normal();
  CHECK(fs::exists(engine) == app::build_info::mpi_engine_built);

  // The installed report.py leaves a mark: the report below must run this copy, not the source tree's.
  {
    const std::string script = slurp(share / "report.py");
    const auto eol = script.find('\n');
    std::ofstream(share / "report.py")
        << script.substr(0, eol + 1)
        << "import sys as _s, os as _o; open(_o.path.join(_s.argv[-1], 'installed-report-used'), 'w').close()\n"
        << script.substr(eol + 1);
  }
  const std::vector<std::string> unset = {"SLIPFRONT_DATA_DIR", "OMPI_COMM_WORLD_SIZE", "PMI_SIZE"};
  const std::string scene = (share / "examples" / "friction_law.toml").string();

  const Output r = run({bin.string(), "run", scene, "--out", "out/friction_law", "--set", "drive.points=5", "--set",
                        "time.steps=500", "-q"},
                       work, {}, unset);
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  CHECK(fs::exists(work / "out" / "friction_law" / "results.h5"));

  std::ofstream(work / "small.toml") << "study = \"small\"\nkind = \"friction_law\"\nscene = \"" << scene
                                      << "\"\nset = [\"drive.points=5\", \"time.steps=500\"]\nseeds = 2\n"
                                         "[vary]\n\"discrete.contacts_per_site\" = [100, 1000, 10000]\n";
  const Output s = run({bin.string(), "study", "small.toml", "--out", "out/studies/small", "-q"}, work, {}, unset);
  INFO(s.out << s.err);
  REQUIRE(s.code == 0);
  CHECK(fs::exists(work / "out" / "studies" / "small" / "study.h5"));

  const fs::path out = work / "out";  // an argument with a quote and a space: no shell to break
  const Output rep = run({bin.string(), "report", out.string()}, root.path, {}, unset);
  INFO(rep.out << rep.err);
  REQUIRE(rep.code == 0);
  CHECK(fs::exists(out / "installed-report-used"));
  REQUIRE(fs::exists(out / "report.md"));
  int pngs = 0;
  for (const auto& e : fs::directory_iterator(out / "figures")) pngs += e.path().extension() == ".png";
  CHECK(pngs >= 2);  // the friction law of the scene, the study's error plot
  const Output check = run({"/usr/bin/python3", (share / "check_report.py").string(), (out / "report.md").string()}, work);
  INFO(check.out << check.err);
  CHECK(check.code == 0);

  // SLIPFRONT_DATA_DIR comes first
  const fs::path data = root.path / "data";
  fs::create_directories(data);
  std::ofstream(data / "report.py") << "import sys, os\nopen(os.path.join(sys.argv[1], 'from-data-dir'), 'w').close()\n";
  const Output env = run({bin.string(), "report", out.string()}, work, {{"SLIPFRONT_DATA_DIR", data.string()}});
  CHECK(env.code == 0);
  CHECK(fs::exists(out / "from-data-dir"));
  // a python that does not exist: an error, not a shell message
  const Output bad = run({bin.string(), "report", out.string(), "--python", "/nonexistent/python3"}, work);
  CHECK(bad.code == 1);
  CHECK(bad.err.find("cannot run '/nonexistent/python3'") != std::string::npos);

  // the installed MPI engine (<prefix>/lib/slipfront), when mpirun is there
  if (app::build_info::mpi_engine_built && !find_program("mpirun").empty()) {
    const Output m = run({"mpirun", "-n", "2", "--bind-to", "none", bin.string(), "study", "small.toml", "--out",
                          "out/studies/mpi", "-q"},
                         work, {{"OMPI_ALLOW_RUN_AS_ROOT", "1"}, {"OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1"}},
                         {"SLIPFRONT_MPI_ENGINE"});
    INFO(m.out << m.err);
    CHECK(m.code == 0);
    CHECK(m.out.find("on 2 MPI ranks") != std::string::npos);
  }
}
