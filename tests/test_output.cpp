// apps/h5out: the HDF5 layout of docs/model.md §5 (docs/output.md), read back with the HDF5 C API.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "apps/h5out.hpp"
#include "compare/runner.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;

namespace {

using testing::TempDir;

// The minimal configuration (edge loading, dx = 2, L = 20, t_end = 2: a few hundred steps), snapshots
// every 0.5.
const std::string tiny = testing::minimal_config() + "[output]\nsnapshot_dt = 0.5\n";

// --- minimal readers on the HDF5 C API -------------------------------------------------------

struct H5 {  // closes an id on scope exit
  hid_t id;
  herr_t (*close)(hid_t);
  ~H5() {
    if (id >= 0) close(id);
  }
};

bool has_attribute(hid_t file, const std::string& object, const std::string& name) {
  return H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string string_attribute(hid_t file, const std::string& object, const std::string& name) {
  H5 attr{H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  REQUIRE(attr.id >= 0);
  H5 type{H5Aget_type(attr.id), H5Tclose};
  REQUIRE(H5Tget_class(type.id) == H5T_STRING);
  REQUIRE(H5Tis_variable_str(type.id) > 0);
  H5 mem{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(mem.id, H5T_VARIABLE);
  H5Tset_cset(mem.id, H5T_CSET_UTF8);  // as written: no ASCII <-> UTF-8 conversion in HDF5
  char* p = nullptr;
  REQUIRE(H5Aread(attr.id, mem.id, &p) >= 0);
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

double double_attribute(hid_t file, const std::string& object, const std::string& name) {
  H5 attr{H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  REQUIRE(attr.id >= 0);
  double v = 0;
  REQUIRE(H5Aread(attr.id, H5T_NATIVE_DOUBLE, &v) >= 0);
  return v;
}

std::vector<hsize_t> shape(hid_t file, const std::string& path) {
  H5 ds{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  REQUIRE(ds.id >= 0);
  H5 space{H5Dget_space(ds.id), H5Sclose};
  std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space.id)));
  H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
  return dims;
}

std::vector<double> read_doubles(hid_t file, const std::string& path) {
  hsize_t n = 1;
  for (const auto d : shape(file, path)) n *= d;
  std::vector<double> v(n);
  H5 ds{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (n > 0) REQUIRE(H5Dread(ds.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0);
  return v;
}

bool exists(hid_t file, const std::string& path) { return H5Lexists(file, path.c_str(), H5P_DEFAULT) > 0; }

// Every dataset below `group` has a non-empty description attribute.
herr_t check_description(hid_t loc, const char* name, const H5O_info_t* info, void* bad) {
  if (info->type == H5O_TYPE_DATASET) {
    if (H5Aexists_by_name(loc, name, "description", H5P_DEFAULT) <= 0) static_cast<std::vector<std::string>*>(bad)->push_back(name);
  }
  return 0;
}

std::vector<std::string> datasets_without_description(hid_t file) {
  std::vector<std::string> bad;
  H5Ovisit(file, H5_INDEX_NAME, H5_ITER_NATIVE, check_description, &bad);
  return bad;
}

struct Run {
  compare::Scene scene;
  std::string toml;
  std::vector<compare::ModelResult> results;
};

Run run_tiny(const std::vector<std::string>& overrides = {}) {
  Run r;
  r.scene = app::parse_scene(tiny, "tiny.toml", overrides);
  r.toml = app::to_toml(r.scene);
  r.results = compare::run_scene(r.scene, {});
  return r;
}

}  // namespace

TEST_CASE("output: a tiny edge-loading run is written in the docs/model.md §5 layout", "[output]") {
  const TempDir dir("output");
  const Run run = run_tiny();
  REQUIRE(run.results.size() == 1);
  const compare::ModelResult& m = run.results[0];
  REQUIRE(m.status == slipfront::compare::RunStatus::complete);

  const fs::path path = dir.path / "results.h5";
  app::RunMeta meta;
  meta.command_line = "slipfront run tiny.toml";
  meta.wall_seconds = 0.25;
  app::write_results(path, run.scene, run.toml, run.results, meta);
  REQUIRE(fs::exists(path));
  // The temporary file was renamed away.
  CHECK_FALSE(fs::exists(app::temporary_path(path)));
  for (const auto& e : fs::directory_iterator(dir.path)) CHECK(e.path().filename() == "results.h5");

  H5 file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  REQUIRE(file.id >= 0);

  // /meta provenance
  CHECK(string_attribute(file.id, "/meta", "status") == "complete");
  CHECK_FALSE(string_attribute(file.id, "/meta", "version").empty());
  CHECK_FALSE(string_attribute(file.id, "/meta", "git_commit").empty());
  CHECK(string_attribute(file.id, "/meta", "compiler").size() > 3);
  CHECK(string_attribute(file.id, "/meta", "hdf5_version").rfind("1.", 0) == 0);
  for (const char* lib : {"boost_version", "tomlplusplus_version", "cli11_version", "eigen_version"})
    CHECK_FALSE(string_attribute(file.id, "/meta", lib).empty());
  const std::string created = string_attribute(file.id, "/meta", "created_utc");
  CHECK(created.size() == 20);  // 2024-01-31T12:00:00Z
  CHECK(created.back() == 'Z');
  CHECK(created[10] == 'T');
  CHECK(double_attribute(file.id, "/meta", "wall_seconds") == 0.25);
  CHECK(string_attribute(file.id, "/meta", "command_line") == "slipfront run tiny.toml");
  CHECK(has_attribute(file.id, "/meta", "message"));

  // /config reloads to the same scene
  const std::string toml = string_attribute(file.id, "/config", "toml");
  REQUIRE_FALSE(toml.empty());
  CHECK(toml == run.toml);
  CHECK(app::same_scene(app::parse_scene(toml, "/config", {}), run.scene));

  // /continuum
  const std::size_t nx = 11;  // L / dx + 1
  CHECK(string_attribute(file.id, "/continuum", "status") == "complete");
  CHECK(double_attribute(file.id, "/continuum", "dt") == m.scalars.at("dt"));
  CHECK(shape(file.id, "/continuum/x") == std::vector<hsize_t>{nx});
  CHECK(read_doubles(file.id, "/continuum/x") == m.x);

  const auto nt = shape(file.id, "/continuum/series/t");
  REQUIRE(nt.size() == 1);
  CHECK(nt[0] > 10);
  for (const char* col : {"drive_force", "max_v", "tip_x", "tip_x_alt"})
    CHECK(shape(file.id, std::string("/continuum/series/") + col) == nt);
  CHECK(read_doubles(file.id, "/continuum/series/t") == m.series.at("t"));
  CHECK(read_doubles(file.id, "/continuum/series/drive_force") == m.series.at("drive_force"));

  const auto ns = shape(file.id, "/continuum/snapshots/t");
  REQUIRE(ns.size() == 1);
  CHECK(ns[0] == 5);  // t = 0, 0.5, 1, 1.5, 2
  for (const char* field : {"A", "sigma_bar", "v", "u"})
    CHECK(shape(file.id, std::string("/continuum/snapshots/") + field) == std::vector<hsize_t>{ns[0], nx});
  CHECK(read_doubles(file.id, "/continuum/snapshots/u") == m.snapshots.at("u"));

  for (const char* e : {"t_star", "t_hat", "c_slow", "c_transient", "c_transient_peak", "x_arrest", "t_arrest",
                        "c_front"}) {
    CHECK(has_attribute(file.id, "/continuum/events", e));
    CHECK(has_attribute(file.id, "/continuum/events", std::string(e) + "_alt"));
  }
  // No yield in 2 time units (t* = 25.7): NaN stays NaN.
  CHECK(std::isnan(double_attribute(file.id, "/continuum/events", "t_star")));
  CHECK_FALSE(exists(file.id, "/continuum/friction_law"));  // only what the scene produced
  CHECK_FALSE(exists(file.id, "/continuum/cycles"));

  CHECK(datasets_without_description(file.id).empty());
}

// The layout of a dataset: contiguous or chunked, and its filters with their parameters.
struct StoredLayout {
  H5D_layout_t layout = H5D_LAYOUT_ERROR;
  std::vector<H5Z_filter_t> filters;
  std::vector<unsigned> deflate_level;  // the gzip filter's parameters (its level), if present
};

StoredLayout stored_layout(hid_t file, const std::string& path) {
  H5 ds{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  REQUIRE(ds.id >= 0);
  H5 dcpl{H5Dget_create_plist(ds.id), H5Pclose};
  REQUIRE(dcpl.id >= 0);
  StoredLayout out;
  out.layout = H5Pget_layout(dcpl.id);
  const int n = H5Pget_nfilters(dcpl.id);
  REQUIRE(n >= 0);
  for (int k = 0; k < n; ++k) {
    unsigned flags = 0, values[8] = {};
    std::size_t nvalues = 8;
    char name[64];
    const H5Z_filter_t f = H5Pget_filter2(dcpl.id, static_cast<unsigned>(k), &flags, &nvalues, values, sizeof name, name, nullptr);
    out.filters.push_back(f);
    if (f == H5Z_FILTER_DEFLATE) out.deflate_level.assign(values, values + nvalues);
  }
  return out;
}

TEST_CASE("output: snapshot fields are contiguous and unfiltered by default, gzip with shuffle on output.deflate", "[output]") {
  const TempDir dir("output");
  const std::vector<std::string> fields = {"A", "sigma_bar", "v", "u"};
  {
    const Run run = run_tiny();
    CHECK(run.scene.output.deflate == 0);  // the default (docs/output.md "Layout of the fields")
    const fs::path path = dir.path / "default.h5";
    app::write_results(path, run.scene, run.toml, run.results, {});
    H5 file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
    REQUIRE(file.id >= 0);
    for (const auto& f : fields) {
      INFO(f);
      const StoredLayout l = stored_layout(file.id, "/continuum/snapshots/" + f);
      CHECK(l.layout == H5D_CONTIGUOUS);
      CHECK(l.filters.empty());
      H5 ds{H5Dopen2(file.id, ("/continuum/snapshots/" + f).c_str(), H5P_DEFAULT), H5Dclose};
      H5 type{H5Dget_type(ds.id), H5Tclose};
      CHECK(H5Tequal(type.id, H5T_IEEE_F64LE) > 0);  // dtype unchanged: float64
      CHECK(read_doubles(file.id, "/continuum/snapshots/" + f) == run.results[0].snapshots.at(f));
    }
    CHECK(shape(file.id, "/continuum/snapshots/A") == std::vector<hsize_t>{5, 11});
  }
  {
    const Run run = run_tiny({"output.deflate=2"});
    CHECK(run.scene.output.deflate == 2);
    CHECK(run.toml.find("deflate = 2") != std::string::npos);  // in the resolved configuration
    const fs::path path = dir.path / "gzip.h5";
    app::write_results(path, run.scene, run.toml, run.results, {});
    H5 file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
    REQUIRE(file.id >= 0);
    for (const auto& f : fields) {
      INFO(f);
      const StoredLayout l = stored_layout(file.id, "/continuum/snapshots/" + f);
      CHECK(l.layout == H5D_CHUNKED);
      CHECK(l.filters == std::vector<H5Z_filter_t>{H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE});
      CHECK(l.deflate_level == std::vector<unsigned>{2});
      CHECK(read_doubles(file.id, "/continuum/snapshots/" + f) == run.results[0].snapshots.at(f));
    }
    // The 1D datasets are never filtered.
    CHECK(stored_layout(file.id, "/continuum/snapshots/t").filters.empty());
    CHECK(stored_layout(file.id, "/continuum/series/t").filters.empty());
  }
}

TEST_CASE("output: status is the worst of models and run and files are replaced atomically", "[output]") {
  const TempDir dir("output");
  Run run = run_tiny({"output.snapshot_dt=0"});
  const fs::path path = dir.path / "results.h5";
  app::write_results(path, run.scene, run.toml, run.results, {});
  {
    H5 file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
    REQUIRE(file.id >= 0);
    CHECK_FALSE(exists(file.id, "/continuum/snapshots"));  // snapshot_dt = 0: none
  }

  run.results[0].status = compare::RunStatus::interrupted;
  run.results[0].message = "stopped at t = 1";
  app::write_results(path, run.scene, run.toml, run.results, {});  // replaces the previous file
  {
    H5 file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
    REQUIRE(file.id >= 0);
    CHECK(string_attribute(file.id, "/meta", "status") == "interrupted");
    CHECK(string_attribute(file.id, "/continuum", "status") == "interrupted");
    CHECK(string_attribute(file.id, "/meta", "message").find("stopped at t = 1") != std::string::npos);
  }

  app::RunMeta failed;
  failed.status = compare::RunStatus::failed;
  failed.message = "the run stopped with an error";
  app::write_results(path, run.scene, run.toml, {}, failed);  // nothing to show but the reason
  {
    H5 file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
    REQUIRE(file.id >= 0);
    CHECK(string_attribute(file.id, "/meta", "status") == "failed");
    CHECK(string_attribute(file.id, "/meta", "message") == "the run stopped with an error");
    CHECK_FALSE(exists(file.id, "/continuum"));
  }

  std::vector<compare::ModelResult> two(2);
  two[0].status = compare::RunStatus::failed;
  two[1].status = compare::RunStatus::interrupted;
  CHECK(app::overall_status(two) == compare::RunStatus::failed);
  two[0].status = compare::RunStatus::complete;
  CHECK(app::overall_status(two) == compare::RunStatus::interrupted);
  two[1].status = compare::RunStatus::complete;
  CHECK(app::overall_status(two) == compare::RunStatus::complete);
  CHECK(app::overall_status(two, compare::RunStatus::failed) == compare::RunStatus::failed);

  // A directory that does not exist: OutputError, no temporary file left behind.
  const fs::path nowhere = dir.path / "missing" / "results.h5";
  CHECK_THROWS_AS(app::write_results(nowhere, run.scene, run.toml, run.results, {}), app::OutputError);
  CHECK_FALSE(fs::exists(app::temporary_path(nowhere)));
}

TEST_CASE("output: 0D friction-law sweep and contact tables", "[output]") {
  const TempDir dir("output");
  Run run;
  run.scene = app::parse_scene(tiny, "sweep.toml",
                               {"drive.loading=imposed_rate", "drive.points=4", "drive.v_min=0.1", "drive.v_max=10",
                                "time.steps=200", "time.slip_end=5", "measure.batches=4"});
  run.toml = app::to_toml(run.scene);
  run.results = compare::run_scene(run.scene, {});
  REQUIRE(run.results.size() == 1);
  // Contact statistics as the discrete model will produce them (1D columns and a 2D table).
  run.results[0].contacts["lifetimes"] = {1.0, 2.0, 3.0};
  run.results[0].contacts_2d["age_histogram"] = {3, {1, 2, 3, 4, 5, 6}};
  run.results[0].labels["representation"] = "agent";

  const fs::path path = dir.path / "results.h5";
  app::write_results(path, run.scene, run.toml, run.results, {});
  H5 file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  REQUIRE(file.id >= 0);
  for (const char* col : {"v", "sigma", "sigma_stderr", "A"})
    CHECK(shape(file.id, std::string("/continuum/friction_law/") + col) == std::vector<hsize_t>{4});
  const auto v = read_doubles(file.id, "/continuum/friction_law/v");
  CHECK(v.front() == Approx(0.1));
  CHECK(v.back() == Approx(10.0));
  CHECK(shape(file.id, "/continuum/x") == std::vector<hsize_t>{1});
  CHECK(shape(file.id, "/continuum/contacts/lifetimes") == std::vector<hsize_t>{3});
  CHECK(shape(file.id, "/continuum/contacts/age_histogram") == std::vector<hsize_t>{2, 3});
  CHECK(read_doubles(file.id, "/continuum/contacts/age_histogram") == std::vector<double>{1, 2, 3, 4, 5, 6});
  CHECK(string_attribute(file.id, "/continuum", "representation") == "agent");
  CHECK(datasets_without_description(file.id).empty());
}
