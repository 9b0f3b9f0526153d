// Golden regression files (issue 9): small stored results of a few scenes — both models, every
// integrator, the count and agent representations, threshold disorder — rerun and compared field by
// field, so that silent drift of any result is caught.
//
// Each case is tests/golden/<case>.toml with its stored result tests/golden/<case>.h5, regenerated
// only by `bash scripts/golden.sh` (with the reason in the commit message: tests/golden/README.md).
// The test runs the program on the .toml and compares every float64 dataset and every numeric
// attribute of the stored file outside /meta (provenance and wall times) with the fresh one:
//   |fresh − golden| ≤ rtol · max(1, max |golden| over the dataset) elementwise, NaN where NaN,
// with rtol = 1e-12 (the arithmetic of the code that wrote them, up to the last bits: any change of
// the algorithm, or of the order of its floating-point operations, beyond round-off, fails). Datasets
// and attributes the stored file has must exist in the fresh one (the layout may grow, not shrink).
// Wall-time attributes (`wall_seconds`) are skipped.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "scenes.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double rtol = 1e-12;

struct H5 {  // closes an id on scope exit
  hid_t id;
  herr_t (*close)(hid_t);
  ~H5() {
    if (id >= 0) close(id);
  }
};

// Every float64 dataset (path → values) and numeric attribute (path@name → value) of a file,
// outside /meta.
struct Contents {
  std::map<std::string, std::vector<double>> datasets;
  std::map<std::string, double> attributes;
};

herr_t read_attribute(hid_t obj, const char* name, const H5A_info_t*, void* data) {
  auto* out = static_cast<std::pair<std::string, Contents*>*>(data);
  if (std::string(name) == "wall_seconds") return 0;
  H5 attr{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  H5 type{H5Aget_type(attr.id), H5Tclose};
  const H5T_class_t cls = H5Tget_class(type.id);
  if (cls != H5T_FLOAT && cls != H5T_INTEGER) return 0;
  H5 space{H5Aget_space(attr.id), H5Sclose};
  if (H5Sget_simple_extent_npoints(space.id) != 1) return 0;
  double v = 0;
  if (H5Aread(attr.id, H5T_NATIVE_DOUBLE, &v) < 0) return -1;
  out->second->attributes[out->first + "@" + name] = v;
  return 0;
}

herr_t visit(hid_t root, const char* name, const H5O_info_t* info, void* data) {
  auto* c = static_cast<Contents*>(data);
  const std::string path = std::string("/") + (std::string(name) == "." ? "" : name);
  if (path.rfind("/meta", 0) == 0) return 0;
  H5 obj{H5Oopen(root, name, H5P_DEFAULT), H5Oclose};
  std::pair<std::string, Contents*> ctx{path, c};
  hsize_t idx = 0;
  H5Aiterate2(obj.id, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, read_attribute, &ctx);
  if (info->type != H5O_TYPE_DATASET) return 0;
  H5 type{H5Dget_type(obj.id), H5Tclose};
  if (H5Tget_class(type.id) != H5T_FLOAT) return 0;
  H5 space{H5Dget_space(obj.id), H5Sclose};
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.id)));
  if (!v.empty() && H5Dread(obj.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) return -1;
  c->datasets[path] = std::move(v);
  return 0;
}

Contents read_contents(const fs::path& file) {
  H5 f{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  REQUIRE(f.id >= 0);
  Contents c;
  REQUIRE(H5Ovisit2(f.id, H5_INDEX_NAME, H5_ITER_NATIVE, visit, &c, H5O_INFO_BASIC) >= 0);
  return c;
}

bool same(double golden, double fresh, double scale) {
  if (std::isnan(golden) || std::isnan(fresh)) return std::isnan(golden) && std::isnan(fresh);
  if (std::isinf(golden) || std::isinf(fresh)) return golden == fresh;
  return std::abs(fresh - golden) <= rtol * scale;
}

}  // namespace

TEST_CASE("golden: stored results of every golden case are reproduced field by field") {
  const fs::path dir = fs::path(SLIPFRONT_SOURCE_DIR) / "tests" / "golden";
  std::vector<std::string> cases;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".toml") cases.push_back(e.path().stem().string());
  std::sort(cases.begin(), cases.end());
  REQUIRE(cases.size() >= 9);
  slipfront::testing::TempDir tmp("golden");
  for (const auto& c : cases) {
    DYNAMIC_SECTION(c) {
      const fs::path out = tmp.path / c;
      const std::string cmd = std::string(SLIPFRONT_BINARY) + " run " + (dir / (c + ".toml")).string() + " --out " +
                              out.string() + " --force --quiet > /dev/null";
      REQUIRE(std::system(cmd.c_str()) == 0);
      const Contents golden = read_contents(dir / (c + ".h5"));
      const Contents fresh = read_contents(out / "results.h5");
      REQUIRE(golden.datasets.size() >= 10);
      double worst = 0.0;
      std::string worst_at;
      for (const auto& [path, g] : golden.datasets) {
        INFO(c << ": dataset " << path);
        const auto it = fresh.datasets.find(path);
        REQUIRE(it != fresh.datasets.end());
        const auto& f = it->second;
        REQUIRE(f.size() == g.size());
        double scale = 1.0;
        for (double x : g)
          if (std::isfinite(x)) scale = std::max(scale, std::abs(x));
        std::size_t bad = 0, first = 0;
        for (std::size_t k = 0; k < g.size(); ++k) {
          if (!same(g[k], f[k], scale) && bad++ == 0) first = k;
          if (std::isfinite(g[k]) && std::isfinite(f[k]) && std::abs(f[k] - g[k]) / scale > worst) {
            worst = std::abs(f[k] - g[k]) / scale;
            worst_at = path;
          }
        }
        INFO(bad << " element(s) differ; the first, " << first << ": golden " << g[first] << ", fresh " << f[first]);
        REQUIRE(bad == 0);
      }
      for (const auto& [key, g] : golden.attributes) {
        INFO(c << ": attribute " << key);
        const auto it = fresh.attributes.find(key);
        REQUIRE(it != fresh.attributes.end());
        REQUIRE(same(g, it->second, std::max(1.0, std::abs(g))));
      }
      WARN(c << ": largest relative difference " << worst << (worst_at.empty() ? "" : " (" + worst_at + ")"));
    }
  }
}
