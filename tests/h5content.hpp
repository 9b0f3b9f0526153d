#pragma once
// Everything in an HDF5 file, for tests that compare two files bit for bit: every dataset (read as
// float64, every one slipfront writes is) and every attribute (numbers as float64, strings), keyed
// by path ("/discrete/series/t", "/discrete/events@t_hat"). Walks the groups with the plain C API.
#include <hdf5.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace slipfront::testing {

struct H5Content {
  std::map<std::string, std::vector<double>> datasets;
  std::map<std::string, double> numbers;       ///< numeric attributes, "<object>@<name>"
  std::map<std::string, std::string> strings;  ///< string attributes
};

namespace detail {

inline void read_attributes(hid_t obj, const std::string& path, H5Content& c) {
  struct Ctx {
    const std::string* path;
    H5Content* c;
  } ctx{&path, &c};
  hsize_t idx = 0;
  auto visit = [](hid_t loc, const char* name, const H5A_info_t*, void* data) -> herr_t {
    auto* x = static_cast<Ctx*>(data);
    const hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
    const hid_t t = H5Aget_type(a);
    const std::string key = *x->path + "@" + name;
    if (H5Tget_class(t) == H5T_STRING) {
      const hid_t mem = H5Tcopy(H5T_C_S1);
      H5Tset_size(mem, H5T_VARIABLE);
      H5Tset_cset(mem, H5Tget_cset(t));
      char* p = nullptr;
      H5Aread(a, mem, &p);
      x->c->strings[key] = p ? p : "";
      H5free_memory(p);
      H5Tclose(mem);
    } else {
      double v = 0;
      H5Aread(a, H5T_NATIVE_DOUBLE, &v);
      x->c->numbers[key] = v;
    }
    H5Tclose(t);
    H5Aclose(a);
    return 0;
  };
  H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, &idx, visit, &ctx);
}

inline void walk(hid_t group, const std::string& path, H5Content& c) {
  read_attributes(group, path.empty() ? "/" : path, c);
  H5G_info_t info{};
  H5Gget_info(group, &info);
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    char name[512] = "";
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
    const std::string child = path + "/" + name;
    const hid_t obj = H5Oopen(group, name, H5P_DEFAULT);
    if (H5Iget_type(obj) == H5I_GROUP) {
      walk(obj, child, c);
    } else {
      const hid_t space = H5Dget_space(obj);
      const hssize_t n = H5Sget_simple_extent_npoints(space);
      std::vector<double> v(static_cast<std::size_t>(n));
      if (n > 0) H5Dread(obj, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
      c.datasets[child] = std::move(v);
      H5Sclose(space);
      read_attributes(obj, child, c);
    }
    H5Oclose(obj);
  }
}

}  // namespace detail

inline H5Content read_h5(const std::filesystem::path& file) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) throw std::runtime_error("cannot open " + file.string());
  H5Content c;
  detail::walk(f, "", c);
  H5Fclose(f);
  return c;
}

inline bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Every key (dataset or attribute) that differs between a and b or is in only one of them, unless
/// ignore(key); values compared bit for bit.
inline std::vector<std::string> differences(const H5Content& a, const H5Content& b,
                                            const std::function<bool(const std::string&)>& ignore) {
  std::vector<std::string> d;
  auto compare = [&](const auto& ma, const auto& mb, auto same) {
    for (const auto& [k, v] : ma) {
      if (ignore(k)) continue;
      const auto it = mb.find(k);
      if (it == mb.end()) d.push_back(k + " only in the first file");
      else if (!same(v, it->second)) d.push_back(k + " differs");
    }
    for (const auto& [k, v] : mb)
      if (!ignore(k) && !ma.count(k)) d.push_back(k + " only in the second file");
  };
  compare(a.datasets, b.datasets, [](const auto& x, const auto& y) { return same_bits(x, y); });
  compare(a.numbers, b.numbers, [](double x, double y) { return same_bits(x, y); });
  compare(a.strings, b.strings, [](const std::string& x, const std::string& y) { return x == y; });
  return d;
}

/// Two results files of the same run: every dataset and attribute, but the provenance of /meta
/// (times, command line) and the wall times. /meta status and config_hash must agree.
inline std::vector<std::string> run_file_differences(const std::filesystem::path& a, const std::filesystem::path& b) {
  return differences(read_h5(a), read_h5(b), [](const std::string& k) {
    if (k.size() >= 13 && k.compare(k.size() - 13, 13, "@wall_seconds") == 0) return true;
    return k.rfind("/meta@", 0) == 0 && k != "/meta@status" && k != "/meta@config_hash" && k != "/meta@scene" &&
           k != "/meta@models";
  });
}

/// Two study.h5 files: the analysis (/study: tables, scalars, definitions, notes, the runs), not the
/// provenance (/meta) nor how the runs were obtained (/study/runs engine, workers, skipped, computed,
/// untrusted).
inline std::vector<std::string> study_differences(const std::filesystem::path& a, const std::filesystem::path& b) {
  return differences(read_h5(a), read_h5(b), [](const std::string& k) {
    return k.rfind("/meta", 0) == 0 || k == "/study/runs/skipped" || k == "/study/runs@engine" ||
           k == "/study/runs@workers" || k == "/study/runs@skipped" || k == "/study/runs@computed" ||
           k == "/study/runs@untrusted";  // how this invocation got the runs, not what they are
  });
}

/// The dimensions of the dataset `path` of `file` (std::runtime_error when either cannot be opened).
inline std::vector<hsize_t> dataset_shape(const std::filesystem::path& file, const std::string& path) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) throw std::runtime_error("cannot open " + file.string());
  const hid_t d = H5Dopen2(f, path.c_str(), H5P_DEFAULT);
  if (d < 0) {
    H5Fclose(f);
    throw std::runtime_error("no dataset " + path + " in " + file.string());
  }
  const hid_t sp = H5Dget_space(d);
  std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(sp)));
  H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  return dims;
}

}  // namespace slipfront::testing
