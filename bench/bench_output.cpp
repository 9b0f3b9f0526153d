// What the snapshot fields of a results file cost to write, per HDF5 layout (issue 22; docs/output.md
// "Layout of the fields", docs/performance.md §14), all in one run, plain main:
//   1. the scenes are run as `slipfront run` runs them (apps::load_scene on configs/<scene>.toml with the
//      --set overrides below, compare::run_scene_alongside) and their fields kept: every model's
//      snapshots/<field> [ns, nx] and bulk/<field> [nb, nyk, nxk];
//   2. each candidate layout writes those fields the way apps/h5out.cpp writes a file (HDF5's in-memory
//      driver, the image written to a new file and fsync'ed): bytes of the image, the write time (image ms:
//      until the image is in memory; write ms: with the write and fsync)
//      (median of $SLIPFRONT_BENCH_REPEATS, default 7; layouts interleaved, so the machine's noise falls
//      on all of them alike), and the ratio of the time against gzip 4 + shuffle in 128 KiB chunks
//      (the layout of every file before issue 22) measured in this same run;
//   3. the whole results file as the program writes it (app::write_results) with the default
//      output.deflate and with output.deflate = 4 (the old layout).
// Lossless layouts only are candidates for the default (the fields are measured); float32 is printed
// for scale (it is lossy: not a candidate), scaleoffset is not run at all (lossy on floats).
// SLIPFRONT_BENCH_QUICK=1: fig1 adaptive continuum only, 2 repeats (the default test tier runs it).
#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "apps/h5out.hpp"
#include "compare/alongside.hpp"

using namespace slipfront;
namespace fs = std::filesystem;

namespace {

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Field {
  std::string name;  // "/continuum/snapshots/A"
  const std::vector<double>* data;
  std::vector<hsize_t> dims;
};

enum class Chunk { contiguous, rows128k, one_row, rows1m, whole };

struct Layout {
  std::string name;
  Chunk chunk = Chunk::contiguous;
  bool shuffle = false;
  int deflate = 0;         // 0: none
  bool szip = false;
  bool nbit = false;
  bool float32 = false;    // lossy: printed for scale, not a candidate
};

std::vector<hsize_t> chunk_of(Chunk c, const std::vector<hsize_t>& dims) {
  hsize_t total = 1;
  for (const auto d : dims) total *= d;
  const hsize_t cols = std::max<hsize_t>(total / dims[0], 1);  // values per row (rank 3: per plane)
  hsize_t rows = dims[0];
  switch (c) {
    case Chunk::rows128k: rows = std::clamp<hsize_t>(16384 / cols, 1, dims[0]); break;  // apps/h5out.cpp before
    case Chunk::one_row: rows = 1; break;
    case Chunk::rows1m: rows = std::clamp<hsize_t>(131072 / cols, 1, dims[0]); break;
    case Chunk::whole: case Chunk::contiguous: break;
  }
  std::vector<hsize_t> chunk = dims;
  chunk[0] = rows;
  return chunk;
}

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "bench_output: run failed: %s\n", what.c_str());
  std::exit(1);
}

void check(herr_t rc, const std::string& what) {
  if (rc < 0) fail("HDF5: cannot " + what);
}

// Writes `fields` with `layout` as apps/h5out.cpp writes a file (in memory, then one write and fsync);
// returns the bytes of the file and adds the time until the image is in memory to `*image_seconds`.
// (Groups are flattened into dataset names: they cost the same in every layout.)
std::size_t write_fields(const fs::path& path, const std::vector<Field>& fields, const Layout& layout,
                         double* image_seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  check(H5Pset_fapl_core(fapl, 1 << 20, 0), "select the in-memory driver");
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  if (file < 0) fail("create " + path.string());
  for (const auto& f : fields) {
    const auto rank = static_cast<int>(f.dims.size());
    const hid_t space = H5Screate_simple(rank, f.dims.data(), nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (layout.chunk != Chunk::contiguous) {
      const auto chunk = chunk_of(layout.chunk, f.dims);
      check(H5Pset_chunk(dcpl, rank, chunk.data()), "chunk " + f.name);
    }
    if (layout.shuffle) check(H5Pset_shuffle(dcpl), "shuffle " + f.name);
    if (layout.nbit) check(H5Pset_nbit(dcpl), "nbit " + f.name);
    if (layout.szip) check(H5Pset_szip(dcpl, H5_SZIP_NN_OPTION_MASK, 32), "szip " + f.name);
    if (layout.deflate > 0) check(H5Pset_deflate(dcpl, static_cast<unsigned>(layout.deflate)), "deflate " + f.name);
    std::string flat = f.name.substr(1);
    std::replace(flat.begin(), flat.end(), '/', '.');
    const hid_t ds = H5Dcreate2(file, flat.c_str(), layout.float32 ? H5T_IEEE_F32LE : H5T_IEEE_F64LE, space,
                                H5P_DEFAULT, dcpl, H5P_DEFAULT);
    if (ds < 0) fail("create " + f.name + " with layout " + layout.name);
    check(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, f.data->data()), "write " + f.name);
    H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(space);
  }
  check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flush");
  const ssize_t size = H5Fget_file_image(file, nullptr, 0);
  std::vector<char> image(static_cast<std::size_t>(size));
  if (H5Fget_file_image(file, image.data(), image.size()) != size) fail("get the file image");
  H5Fclose(file);
  H5Pclose(fapl);
  *image_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const fs::path out = path.string() + ".out";
  fs::remove(out);
  const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) fail("open " + out.string());
  if (::write(fd, image.data(), image.size()) != size || ::fsync(fd) != 0 || ::close(fd) != 0)
    fail("write " + out.string());
  return image.size();
}

// Whether the file `write_fields` wrote holds every field bit for bit (float32: never).
bool exact(const fs::path& path, const std::vector<Field>& fields) {
  const hid_t file = H5Fopen((path.string() + ".out").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) fail("reopen " + path.string());
  bool same = true;
  for (const auto& f : fields) {
    std::string flat = f.name.substr(1);
    std::replace(flat.begin(), flat.end(), '/', '.');
    std::vector<double> back(f.data->size());
    const hid_t ds = H5Dopen2(file, flat.c_str(), H5P_DEFAULT);
    if (ds < 0 || H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()) < 0) fail("read " + f.name);
    H5Dclose(ds);
    same = same && std::memcmp(back.data(), f.data->data(), back.size() * sizeof(double)) == 0;
  }
  H5Fclose(file);
  return same;
}

double seconds_of(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Case {
  std::string label, config;
  std::vector<std::string> overrides;
};

}  // namespace

int main() {
  const bool quick = std::getenv("SLIPFRONT_BENCH_QUICK") != nullptr;
  const int repeats = env_int("SLIPFRONT_BENCH_REPEATS", quick ? 2 : 7);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);

  std::vector<Layout> layouts = {
      {"gzip4+shuffle, 128 KiB chunks (old default)", Chunk::rows128k, true, 4},
      {"contiguous, no filter", Chunk::contiguous},
      {"chunked 128 KiB, no filter", Chunk::rows128k},
      {"chunked one row, no filter", Chunk::one_row},
  };
  for (int level = 1; level <= 4; ++level)
    for (const bool shuffle : {false, true})
      if (!(level == 4 && shuffle))
        layouts.push_back({"gzip" + std::to_string(level) + (shuffle ? "+shuffle" : "") + ", 128 KiB chunks",
                           Chunk::rows128k, shuffle, level});
  layouts.push_back({"gzip1+shuffle, one-row chunks", Chunk::one_row, true, 1});
  layouts.push_back({"gzip1+shuffle, 1 MiB chunks", Chunk::rows1m, true, 1});
  layouts.push_back({"gzip1+shuffle, whole-dataset chunk", Chunk::whole, true, 1});
  layouts.push_back({"gzip4+shuffle, 1 MiB chunks", Chunk::rows1m, true, 4});
  layouts.push_back({"nbit (float64: full precision), 128 KiB", Chunk::rows128k, false, 0, false, true});
  const bool szip = H5Zfilter_avail(H5Z_FILTER_SZIP) > 0;
  unsigned szip_info = 0;
  if (szip) H5Zget_filter_info(H5Z_FILTER_SZIP, &szip_info);
  if (szip && (szip_info & H5Z_FILTER_CONFIG_ENCODE_ENABLED))
    layouts.push_back({"szip NN 32, 128 KiB chunks", Chunk::rows128k, false, 0, true});
  layouts.push_back({"float32 contiguous (LOSSY, scale only)", Chunk::contiguous, false, 0, false, false, true});
  std::printf("HDF5 %s; filters available: deflate %d, shuffle %d, szip %d (encode %d), nbit %d, scaleoffset %d "
              "(lossy on floats: not run); repeats %d\n",
              app::library_versions().hdf5.c_str(), H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0,
              H5Zfilter_avail(H5Z_FILTER_SHUFFLE) > 0, szip, (szip_info & H5Z_FILTER_CONFIG_ENCODE_ENABLED) != 0,
              H5Zfilter_avail(H5Z_FILTER_NBIT) > 0, H5Zfilter_avail(H5Z_FILTER_SCALEOFFSET) > 0, repeats);

  std::vector<Case> cases = {{"fig1 adaptive continuum", "fig1.toml", {"models=[\"continuum\"]", "time.integrator=adaptive"}}};
  if (!quick) {
    cases.push_back({"fig1 (continuum + discrete, explicit)", "fig1.toml", {}});
    cases.push_back({"fig1_strip continuum (bulk)", "fig1_strip.toml", {"models=[\"continuum\"]"}});
  }

  const fs::path dir = fs::temp_directory_path() / ("bench_output." + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const auto& c : cases) {
    compare::Scene scene = app::load_scene(fs::path(SLIPFRONT_SOURCE_DIR) / "configs" / c.config, c.overrides);
    const compare::SceneResult sr = compare::run_scene_alongside(scene, {});
    std::vector<Field> fields;
    std::size_t values = 0;
    for (const auto& r : sr.models) {
      const hsize_t ns = r.snapshot_t.size(), nx = r.x.size();
      for (const auto& [name, v] : r.snapshots) fields.push_back({"/" + r.model + "/snapshots/" + name, &v, {ns, nx}});
      for (const auto& [name, v] : r.bulk)
        fields.push_back({"/" + r.model + "/bulk/" + name, &v, {r.bulk_t.size(), r.bulk_y.size(), r.bulk_x.size()}});
    }
    for (const auto& f : fields) values += f.data->size();
    std::printf("\n%s (configs/%s", c.label.c_str(), c.config.c_str());
    for (const auto& o : c.overrides) std::printf(" --set '%s'", o.c_str());
    std::printf("): %zu fields, %.2f MB of float64\n", fields.size(), 8e-6 * static_cast<double>(values));

    std::vector<std::vector<double>> times(layouts.size()), image_times(layouts.size());
    std::vector<std::size_t> bytes(layouts.size());
    for (int k = 0; k < repeats + 1; ++k)  // the first round warms up (page cache, allocator): not counted
      for (std::size_t l = 0; l < layouts.size(); ++l) {
        double image = 0.0;
        const double s =
            seconds_of([&] { bytes[l] = write_fields(dir / ("f" + std::to_string(l)), fields, layouts[l], &image); });
        if (k > 0) times[l].push_back(s), image_times[l].push_back(image);
      }
    const double base = median(times[0]);
    std::printf("  %-44s %10s %9s %9s %9s %9s %6s\n", "layout of the fields", "bytes", "vs gzip4", "write ms",
                "vs gzip4", "image ms", "exact");
    for (std::size_t l = 0; l < layouts.size(); ++l)
      std::printf("  %-44s %10zu %9.2f %9.2f %9.2f %9.2f %6s\n", layouts[l].name.c_str(), bytes[l],
                  static_cast<double>(bytes[l]) / static_cast<double>(bytes[0]), 1e3 * median(times[l]),
                  median(times[l]) / base, 1e3 * median(image_times[l]),
                  exact(dir / ("f" + std::to_string(l)), fields) ? "yes" : "NO");

    // The whole file as the program writes it: the default output.deflate against the old layout.
    const std::string resolved = app::to_toml(scene);
    std::vector<double> t_default, t_old;
    std::size_t b_default = 0, b_old = 0;
    compare::Scene old = scene;
    old.output.deflate = 4;
    for (int k = 0; k < repeats + 1; ++k) {
      const double a = seconds_of([&] { app::write_results(dir / "default.h5", scene, resolved, sr.models, {}, &sr.comparison); });
      const double b = seconds_of([&] { app::write_results(dir / "old.h5", old, resolved, sr.models, {}, &sr.comparison); });
      if (k > 0) t_default.push_back(a), t_old.push_back(b);
    }
    b_default = fs::file_size(dir / "default.h5");
    b_old = fs::file_size(dir / "old.h5");
    std::printf("  whole results.h5 (app::write_results): default output.deflate = %d: %zu bytes, %.2f ms; "
                "output.deflate = 4: %zu bytes, %.2f ms; ratio default/old %.2f\n",
                scene.output.deflate, b_default, 1e3 * median(t_default), b_old, 1e3 * median(t_old),
                median(t_default) / median(t_old));
  }
  fs::remove_all(dir);
  return 0;
}
