#include "apps/h5in.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <string_view>
#include <utility>

#include "apps/h5out.hpp"
#include "apps/hdf5_handle.hpp"
#include "compare/models.hpp"
#include "core/checksum.hpp"

namespace slipfront::app {
namespace {

namespace fs = std::filesystem;

// RAII for hid_t (apps/hdf5_handle.hpp): errors are InputError("cannot ...").
inline constexpr char input_cannot[] = "cannot ";
using Hid = HdfHandle<InputError, input_cannot>;

bool has_link(hid_t loc, const std::string& name) { return H5Lexists(loc, name.c_str(), H5P_DEFAULT) > 0; }

// Names of the links in a group, in name order.
std::vector<std::string> link_names(hid_t group, const std::string& where) {
  H5G_info_t info{};
  if (H5Gget_info(group, &info) < 0) throw InputError("cannot list " + where);
  std::vector<std::string> names;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const ssize_t n = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    if (n < 0) throw InputError("cannot list " + where);
    std::string name(static_cast<std::size_t>(n) + 1, '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size(), H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(n));
    names.push_back(std::move(name));
  }
  return names;
}

H5I_type_t object_type(hid_t loc, const std::string& name, const std::string& where) {
  Hid obj(H5Oopen(loc, name.c_str(), H5P_DEFAULT), H5Oclose, "open " + where);
  return H5Iget_type(obj.get());
}

std::vector<std::string> attribute_names(hid_t obj, const std::string& where) {
  std::vector<std::string> names;
  hsize_t idx = 0;
  auto collect = [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  if (H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, &idx, collect, &names) < 0)
    throw InputError("cannot list the attributes of " + where);
  return names;
}

H5T_class_t attribute_class(hid_t obj, const std::string& name, const std::string& where) {
  Hid attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + where + " " + name);
  Hid type(H5Aget_type(attr.get()), H5Tclose, "read the type of attribute " + where + " " + name);
  return H5Tget_class(type.get());
}

std::string attr_string(hid_t obj, const std::string& name, const std::string& where) {
  const std::string what = "attribute " + name + " of " + where;
  Hid attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, "open " + what);
  Hid type(H5Aget_type(attr.get()), H5Tclose, "read the type of " + what);
  if (H5Tget_class(type.get()) != H5T_STRING) throw InputError(what + " is not a string");
  if (H5Tis_variable_str(type.get()) > 0) {
    Hid mem(H5Tcopy(H5T_C_S1), H5Tclose, "make a string type");
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
    char* p = nullptr;
    if (H5Aread(attr.get(), mem.get(), &p) < 0) throw InputError("cannot read " + what);
    std::string s = p ? p : "";
    H5free_memory(p);
    return s;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::string s(size, '\0');
  if (size > 0 && H5Aread(attr.get(), type.get(), s.data()) < 0) throw InputError("cannot read " + what);
  s.resize(s.find('\0') == std::string::npos ? s.size() : s.find('\0'));
  return s;
}

// A `status` attribute (h5out's attr_status): one of the RunStatus names, else the file is refused.
compare::RunStatus attr_status(hid_t obj, const std::string& where) {
  const std::string text = attr_string(obj, "status", where);
  try {
    return compare::run_status(text);
  } catch (const std::invalid_argument&) {
    throw InputError(where + " status: '" + text + "' is none of complete, interrupted, failed");
  }
}

std::string attr_string_or(hid_t obj, const std::string& name, const std::string& where, const std::string& fallback) {
  return H5Aexists(obj, name.c_str()) > 0 ? attr_string(obj, name, where) : fallback;
}

double attr_double(hid_t obj, const std::string& name, const std::string& where) {
  const std::string what = "attribute " + name + " of " + where;
  Hid attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, "open " + what);
  double v = 0.0;
  if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v) < 0) throw InputError("cannot read " + what + " as a number");
  return v;
}

// A float64 dataset of any rank, flat (row-major), with its dimensions.
std::vector<double> read_dataset(hid_t loc, const std::string& name, const std::string& where,
                                 std::vector<hsize_t>* dims_out = nullptr) {
  Hid ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + where);
  Hid space(H5Dget_space(ds.get()), H5Sclose, "read the dataspace of " + where);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) throw InputError("cannot read the shape of " + where);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  hsize_t total = 1;
  for (const auto d : dims) total *= d;
  std::vector<double> v(static_cast<std::size_t>(total));
  if (total > 0 && H5Dread(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    throw InputError("cannot read " + where);
  if (dims_out) *dims_out = std::move(dims);
  return v;
}

// Every dataset of a group as columns (the layout of series, cycles, friction_law, ...).
compare::Columns read_columns(hid_t parent, const std::string& group, const std::string& where) {
  compare::Columns cols;
  if (!has_link(parent, group)) return cols;
  Hid g(H5Gopen2(parent, group.c_str(), H5P_DEFAULT), H5Gclose, "open group " + where);
  for (const auto& name : link_names(g.get(), where)) cols[name] = read_dataset(g.get(), name, where + "/" + name);
  return cols;
}

compare::ModelResult read_model(hid_t file, const std::string& m, const ReadOptions& opt) {
  const std::string base = "/" + m;
  Hid g(H5Gopen2(file, m.c_str(), H5P_DEFAULT), H5Gclose, "open group " + base);
  compare::ModelResult r;
  r.model = m;
  // Attributes of /<model>: status, message, wall_seconds, then every other number is a scalar and
  // every other string a label (h5out's model()).
  for (const auto& name : attribute_names(g.get(), base)) {
    if (name == "status") r.status = attr_status(g.get(), base);
    else if (name == "message") r.message = attr_string(g.get(), name, base);
    else if (name == "wall_seconds") r.wall_seconds = attr_double(g.get(), name, base);
    else if (attribute_class(g.get(), name, base) == H5T_STRING) r.labels[name] = attr_string(g.get(), name, base);
    else r.scalars[name] = attr_double(g.get(), name, base);
  }
  if (has_link(g.get(), "x")) r.x = read_dataset(g.get(), "x", base + "/x");
  r.series = read_columns(g.get(), "series", base + "/series");
  if (has_link(g.get(), "events")) {
    Hid e(H5Gopen2(g.get(), "events", H5P_DEFAULT), H5Gclose, "open group " + base + "/events");
    for (const auto& [name, member] : compare::event_fields) {  // every event h5out writes
      if (H5Aexists(e.get(), name) > 0) r.events.*member = attr_double(e.get(), name, base + "/events");
      const std::string alt = std::string(name) + "_alt";
      if (H5Aexists(e.get(), alt.c_str()) > 0) r.events_alt.*member = attr_double(e.get(), alt, base + "/events");
    }
  }
  r.cycles = read_columns(g.get(), "cycles", base + "/cycles");
  r.sequence = read_columns(g.get(), "sequence", base + "/sequence");
  r.friction_law = read_columns(g.get(), "friction_law", base + "/friction_law");
  if (!opt.fields) return r;

  if (has_link(g.get(), "snapshots")) {
    const std::string where = base + "/snapshots";
    Hid s(H5Gopen2(g.get(), "snapshots", H5P_DEFAULT), H5Gclose, "open group " + where);
    for (const auto& name : link_names(s.get(), where)) {
      if (name == "t") r.snapshot_t = read_dataset(s.get(), name, where + "/t");
      else r.snapshots[name] = read_dataset(s.get(), name, where + "/" + name);
    }
  }
  if (has_link(g.get(), "bulk")) {
    const std::string where = base + "/bulk";
    Hid b(H5Gopen2(g.get(), "bulk", H5P_DEFAULT), H5Gclose, "open group " + where);
    for (const auto& name : link_names(b.get(), where)) {
      std::vector<double> v = read_dataset(b.get(), name, where + "/" + name);
      if (name == "t") r.bulk_t = std::move(v);
      else if (name == "x") r.bulk_x = std::move(v);
      else if (name == "y") r.bulk_y = std::move(v);
      else r.bulk[name] = std::move(v);
    }
  }
  if (has_link(g.get(), "contacts")) {
    const std::string where = base + "/contacts";
    Hid c(H5Gopen2(g.get(), "contacts", H5P_DEFAULT), H5Gclose, "open group " + where);
    for (const auto& name : link_names(c.get(), where)) {
      std::vector<hsize_t> dims;
      std::vector<double> v = read_dataset(c.get(), name, where + "/" + name, &dims);
      if (dims.size() == 2) r.contacts_2d[name] = compare::Table2D{static_cast<std::size_t>(dims[1]), std::move(v)};
      else r.contacts[name] = std::move(v);
    }
  }
  return r;
}

// The models of the table that another is compared with (compare::is_reference_model), "a, b".
std::string reference_names() {
  std::string out;
  for (const auto& k : compare::model_kinds)
    if (compare::is_reference_model(k.name)) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

compare::Comparison read_comparison(hid_t file) {
  compare::Comparison c;
  if (!has_link(file, "compare")) return c;
  Hid g(H5Gopen2(file, "compare", H5P_DEFAULT), H5Gclose, "open group /compare");
  c.reference = attr_string_or(g.get(), "reference", "/compare", "continuum");  // absent: the continuum
  if (!compare::is_reference_model(c.reference))  // a model some model is compared with (compare/models.hpp)
    throw InputError("/compare reference names '" + c.reference + "' (expected a reference model of the table: " +
                     reference_names() + ")");
  for (const auto& name : link_names(g.get(), "/compare")) {
    const std::string where = "/compare/" + name;
    if (object_type(g.get(), name, where) == H5I_GROUP) {
      compare::Columns& cols = name == "fields" ? c.fields : c.friction_law;
      if (name != "fields" && name != "friction_law") continue;  // not written by this version
      Hid sub(H5Gopen2(g.get(), name.c_str(), H5P_DEFAULT), H5Gclose, "open group " + where);
      for (const auto& col : link_names(sub.get(), where)) {
        cols[col] = read_dataset(sub.get(), col, where + "/" + col);
        Hid ds(H5Dopen2(sub.get(), col.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + where + "/" + col);
        c.definitions[name + "/" + col] = attr_string_or(ds.get(), "definition", where + "/" + col, "");
      }
    } else {
      const std::vector<double> v = read_dataset(g.get(), name, where);
      if (v.size() != 1) throw InputError(where + " is not a scalar");
      c.metrics[name] = v[0];
      Hid ds(H5Dopen2(g.get(), name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + where);
      c.definitions[name] = attr_string_or(ds.get(), "definition", where, "");
    }
  }
  return c;
}

std::vector<std::string> split_models(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < s.size()) {
    const std::size_t comma = s.find(',', start);
    const std::size_t end = comma == std::string::npos ? s.size() : comma;
    if (end > start) out.push_back(s.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

ResultsHeader read_header(hid_t file) {
  if (!has_link(file, "meta") || !has_link(file, "config"))
    throw InputError("not a slipfront results file (no /meta or /config)");
  ResultsHeader h;
  Hid meta(H5Gopen2(file, "meta", H5P_DEFAULT), H5Gclose, "open group /meta");
  h.status = attr_status(meta.get(), "/meta");
  h.message = attr_string_or(meta.get(), "message", "/meta", "");
  h.config_hash = attr_string_or(meta.get(), "config_hash", "/meta", "");
  h.git_commit = attr_string_or(meta.get(), "git_commit", "/meta", "");
  h.scene = attr_string_or(meta.get(), "scene", "/meta", "");
  h.models = split_models(attr_string_or(meta.get(), "models", "/meta", ""));
  Hid config(H5Gopen2(file, "config", H5P_DEFAULT), H5Gclose, "open group /config");
  h.resolved_toml = attr_string(config.get(), "toml", "/config");
  return h;
}

template <class Read>
auto with_file(const fs::path& path, Read&& read) {
  const QuietHdf5 quiet;
  try {
    Hid file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open the file as HDF5");
    return read(file.get());
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

// A regular file mapped read-only (empty files: no mapping).
class MappedFile {
 public:
  explicit MappedFile(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) throw InputError(path.string() + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd);
      throw InputError(path.string() + ": not a regular file");
    }
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ > 0) {
      void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
      if (p == MAP_FAILED) {
        const int e = errno;
        ::close(fd);
        throw InputError(path.string() + ": cannot map: " + std::strerror(e));
      }
      data_ = static_cast<const char*>(p);
    }
    ::close(fd);
  }
  ~MappedFile() {
    if (data_) ::munmap(const_cast<char*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::string_view bytes() const { return {data_, size_}; }

 private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

// The value after `label` on its line in the block ("" if absent).
std::string block_field(std::string_view block, std::string_view label) {
  const std::size_t at = block.find(label);
  if (at == std::string_view::npos) return "";
  const std::size_t from = at + label.size(), end = block.find('\n', from);
  return std::string(block.substr(from, std::min(end, block.size()) - from));
}

}  // namespace

ChecksumCheck verify_checksum(const fs::path& path) {
  const MappedFile file(path);
  const std::string_view all = file.bytes();
  if (all.substr(0, checksum_magic.size()) != checksum_magic) {
    // Files written before checksums begin with HDF5's signature; anything else is a damaged block.
    constexpr std::string_view hdf5_signature("\x89HDF\r\n\x1a\n", 8);
    if (all.substr(0, hdf5_signature.size()) == hdf5_signature)
      return {Checksum::absent, "no checksum (an HDF5 file without slipfront's checksum block: written before "
                                "checksums, or not by slipfront)"};
    return {Checksum::failed, "damaged: the file begins neither with slipfront's checksum block nor with HDF5's "
                              "signature"};
  }
  if (all.size() < checksum_block_bytes)
    return {Checksum::failed, "truncated: " + std::to_string(all.size()) + " bytes, shorter than its checksum block"};
  const std::string_view block = all.substr(0, checksum_block_bytes), payload = all.substr(checksum_block_bytes);
  const std::string expected = checksum_block(payload);
  if (block == expected) return {Checksum::intact, ""};
  const std::string stored = block_field(block, "xxh3-64 "), stored_size = block_field(block, "\nbytes ");
  const std::string now = core::content_hash_hex(payload);
  if (stored != now)
    return {Checksum::failed, "checksum fails: stored xxh3-64 " + (stored.empty() ? "(unreadable)" : stored) +
                                  ", the " + std::to_string(payload.size()) + " bytes after the block hash to " + now +
                                  (stored_size == std::to_string(payload.size()) ? "" : " (stored size " + stored_size + ")")};
  return {Checksum::failed, "checksum block altered (its hash matches the content, its other bytes do not)"};
}

ResultsHeader read_results_header(const fs::path& path) {
  return with_file(path, [](hid_t file) { return read_header(file); });
}

std::string read_study_name(const fs::path& path) {
  return with_file(path, [](hid_t file) {
    if (!has_link(file, "study")) throw InputError("not a study file (no /study)");
    Hid g(H5Gopen2(file, "study", H5P_DEFAULT), H5Gclose, "open group /study");
    return attr_string(g.get(), "name", "/study");
  });
}

StudyHeader read_study_header(const fs::path& path) {
  return with_file(path, [](hid_t file) {
    if (!has_link(file, "study")) throw InputError("not a study file (no /study)");
    Hid g(H5Gopen2(file, "study", H5P_DEFAULT), H5Gclose, "open group /study");
    return StudyHeader{attr_string(g.get(), "name", "/study"), attr_string(g.get(), "kind", "/study"),
                       attr_string(g.get(), "toml", "/study")};
  });
}

ResultsFile read_results(const fs::path& path, const ReadOptions& options) {
  if (options.verified) {
    const ChecksumCheck c = verify_checksum(path);
    if (c.state != Checksum::intact) throw InputError(path.string() + ": " + c.detail);
  }
  return with_file(path, [&](hid_t file) {
    ResultsFile f;
    f.header = read_header(file);
    for (const auto& m : f.header.models) {
      if (!has_link(file, m)) throw InputError("/meta models names '" + m + "' but there is no group /" + m);
      f.models.push_back(read_model(file, m, options));
    }
    f.comparison = read_comparison(file);
    return f;
  });
}

}  // namespace slipfront::app
