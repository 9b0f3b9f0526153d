#include "apps/h5out.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <CLI/Version.hpp>
#include <algorithm>
#include <boost/crc.hpp>
#include <boost/version.hpp>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <toml++/toml.h>
#include <utility>

#include "apps/build_info.hpp"
#include "apps/hdf5_handle.hpp"
#include "apps/stability.hpp"
#include "continuum/friction_law.hpp"
#include "core/checksum.hpp"

namespace slipfront::app {
namespace {

// ---------------------------------------------------------------------------------------------
// RAII for hid_t (apps/hdf5_handle.hpp): errors are OutputError("HDF5: cannot ...").

inline constexpr char hdf5_cannot[] = "HDF5: cannot ";
using Hid = HdfHandle<OutputError, hdf5_cannot>;

void check(herr_t rc, const std::string& what) {
  if (rc < 0) throw OutputError(hdf5_cannot + what);
}

// ---------------------------------------------------------------------------------------------
// Groups, attributes, datasets.

Hid make_group(hid_t parent, const std::string& name, const std::string& where) {
  return Hid(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
             "create group " + where);
}

void delete_attribute_if_present(hid_t obj, const std::string& name) {
  if (H5Aexists(obj, name.c_str()) > 0) check(H5Adelete(obj, name.c_str()), "replace attribute " + name);
}

void attr_string(hid_t obj, const std::string& name, const std::string& value) {
  delete_attribute_if_present(obj, name);
  Hid type(H5Tcopy(H5T_C_S1), H5Tclose, "make a string type");
  check(H5Tset_size(type.get(), H5T_VARIABLE), "make a string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "make a string type");
  Hid space(H5Screate(H5S_SCALAR), H5Sclose, "make a scalar dataspace");
  Hid attr(H5Acreate2(obj, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
           "create attribute " + name);
  const char* p = value.c_str();
  check(H5Awrite(attr.get(), type.get(), &p), "write attribute " + name);
}

// The `status` attribute of /meta and of each /<model>: the one place a RunStatus is written (its name;
// h5in reads it back with compare::run_status).
void attr_status(hid_t obj, compare::RunStatus status) { attr_string(obj, "status", compare::to_string(status)); }

void attr_double(hid_t obj, const std::string& name, double value) {
  delete_attribute_if_present(obj, name);
  Hid space(H5Screate(H5S_SCALAR), H5Sclose, "make a scalar dataspace");
  Hid attr(H5Acreate2(obj, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
           "create attribute " + name);
  check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, &value), "write attribute " + name);
}

void attr_int(hid_t obj, const std::string& name, long long value) {
  delete_attribute_if_present(obj, name);
  Hid space(H5Screate(H5S_SCALAR), H5Sclose, "make a scalar dataspace");
  Hid attr(H5Acreate2(obj, name.c_str(), H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
           "create attribute " + name);
  check(H5Awrite(attr.get(), H5T_NATIVE_LLONG, &value), "write attribute " + name);
}

// A float64 dataset of shape dims (rank 1, 2 or 3) with a `description` attribute. The fields (snapshots,
// bulk snapshots, the fronts' bulk profiles: rank 2 or 3) pass the scene's output.deflate: 0 (the default)
// writes them contiguous and unfiltered like every other dataset; 1..9 chunks them by whole rows (whole
// [nyk, nxk] planes, at most 128 KiB a chunk) with the byte shuffle and gzip at that level, when the
// filter is available. Measured (bench/bench_output, docs/output.md "Layout of the fields"): on fig1's fields
// gzip 4 + shuffle saves 43% of the bytes and takes ~9x the time of writing them contiguous.
void dataset(hid_t parent, const std::string& name, const double* data, std::vector<hsize_t> dims,
             const std::string& description, const std::string& where, int deflate = 0) {
  const auto rank = static_cast<int>(dims.size());
  Hid space(H5Screate_simple(rank, dims.data(), nullptr), H5Sclose, "make the dataspace of " + where);
  Hid dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "make a property list");
  hsize_t total = 1;
  for (const auto d : dims) total *= d;
  if (deflate > 0 && rank >= 2 && total > 0 && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    const hsize_t cols = total / dims[0];  // values per row (rank 3: per plane)
    const hsize_t rows = std::clamp<hsize_t>(16384 / std::max<hsize_t>(cols, 1), 1, dims[0]);  // ≤ 128 KiB
    std::vector<hsize_t> chunk = dims;
    chunk[0] = rows;
    check(H5Pset_chunk(dcpl.get(), rank, chunk.data()), "chunk " + where);
    check(H5Pset_shuffle(dcpl.get()), "set the shuffle filter on " + where);
    check(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(deflate)), "set the gzip filter on " + where);
  }
  Hid ds(H5Dcreate2(parent, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
         H5Dclose, "create dataset " + where);
  if (total > 0) check(H5Dwrite(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write " + where);
  attr_string(ds.get(), "description", description);
}

void dataset_1d(hid_t parent, const std::string& name, const std::vector<double>& v, const std::string& description,
                const std::string& where) {
  dataset(parent, name, v.data(), {v.size()}, description, where);
}

// ---------------------------------------------------------------------------------------------
// What each dataset means (docs/output.md says the same at more length).

std::string description_of(const std::string& group, const std::string& name) {
  static const std::map<std::string, std::string> known = {
      {"x", "node positions x along the interface [nx] (0D scenes: the single site, x = 0)"},
      {"normal_load",
       "the prescribed normal load p(x)/p_0 at x [nx] (interface.load_x, load_p interpolated; docs/model.md §12): "
       "provenance, written only with a profile"},
      {"resting_area", "the resting contact area (p/p_0)^m at x [nx] that the law relaxed towards (docs/model.md §12)"},
      {"series/t", "time t of each series sample (cadence output.series_dt)"},
      {"series/drive_force",
       "drive force F = K (v_d t - u(0,t)) (edge loading, spring block; 0 for homogeneous loading; "
       "imposed slip rate: the frictional stress sigma)"},
      {"series/max_v", "max over x of |v| during the last step (imposed slip rate: |v|)"},
      {"series/tip_x",
       "front tip: largest x with A < measure.A_tip, interpolated between nodes, from the latest tip sample "
       "(cadence measure.sample_dt); NaN when A >= A_tip everywhere"},
      {"series/tip_x_alt", "as tip_x for the threshold measure.A_tip_alt"},
      {"series/A", "contact-area fraction A of the single site (0D)"},
      {"series/sigma_bar", "interfacial elastic stress sigma_bar of the single site (0D)"},
      {"series/sigma", "frictional stress sigma = sigma_bar + eta v of the single site (0D)"},
      {"series/slip_rate", "slip rate v of the single site (0D)"},
      {"series/slip", "slip u of the single site (0D)"},
      {"series/energy_drive_work", "work done by the drive since t = 0 (energy budget, output.energy)"},
      {"series/energy_mechanical",
       "kinetic + elastic + spring energy minus its initial value (energy budget, output.energy)"},
      {"series/energy_viscous", "energy dissipated by the eta v term since t = 0 (energy budget, output.energy)"},
      {"series/energy_interfacial",
       "work of the interfacial stress sigma_bar on the slip since t = 0 (energy budget, output.energy)"},
      {"series/energy_residual",
       "drive work - mechanical - viscous - interfacial: the error of the energy budget (output.energy)"},
      {"series/energy_time",
       "time t^n at which the energy budget terms hold: the start of the last step, one step behind series/t "
       "(output.energy)"},
      {"contacts/lifetime_hist_edges", "bin edges of the attached-lifetime histogram [nb + 1] (log spaced, 0 .. inf)"},
      {"contacts/lifetime_hist_counts", "completed attachments per lifetime bin [nb]"},
      {"contacts/lifetime_total", "number of completed attachments counted [1]"},
      {"contacts/lifetimes", "raw attached lifetimes (only when at most 100000 were recorded)"},
      {"contacts/lifetime_start_t", "attachment time of each raw lifetime"},
      {"contacts/detached_hist_edges", "bin edges of the detached-duration histogram [nb + 1]"},
      {"contacts/detached_hist_counts", "completed detached periods per duration bin [nb]"},
      {"contacts/detached_total", "number of completed detached periods counted [1]"},
      {"contacts/detached_durations", "raw detached durations (only when at most 100000 were recorded)"},
      {"contacts/detached_start_t", "detachment time of each raw detached duration"},
      {"contacts/snapshot_t", "times of the contact snapshots (cadence output.contact_snapshot_dt) [ns]"},
      {"contacts/age_hist_edges", "bin edges of the age histogram of attached contacts [nb + 1]"},
      {"contacts/age_hist_counts", "ages t - t_attach of the attached contacts at each snapshot [ns, nb]"},
      {"contacts/threshold_hist_edges", "bin edges of the threshold histogram of attached contacts [nb + 1]"},
      {"contacts/threshold_hist_counts", "yield thresholds of the attached contacts at each snapshot [ns, nb]"},
      {"contacts/detachments_per_site",
       "detachments per site in (t_{k-1}, t_k] between snapshots (row 0: since the start) [ns, nx]"},
      {"contacts/attachments_per_site", "attachments per site in the same intervals [ns, nx]"},
      // by region and phase (docs/model.md §7.2, docs/contacts.md): counted by the agent; expected counts
      // predicted from its fields by the continuum
      {"contacts/class_time_edges",
       "bin edges of the class tables [nc + 1]: 0, 1e-3 .. 1e4 (5 per decade, edges of the log time edges), inf"},
      {"contacts/class_lifetime_counts",
       "completed attachments by lifetime [12, nc], row 3 phase + region (phase: before yield, slow front, transient, "
       "after arrest; region: behind, tip band, ahead of the A_tip_alt front), classed at the detachment; continuum: "
       "expected counts predicted from its fields"},
      {"contacts/class_age_counts",
       "ages of the attached contacts summed over the contact snapshots [12, nc], classed at each snapshot (rows as "
       "class_lifetime_counts); continuum: expected counts"},
      {"contacts/region_age_counts",
       "ages of the attached contacts at each contact snapshot by region [ns, 3 nc] (behind | tip | ahead, nc bins "
       "each); continuum: expected counts"},
      {"contacts/contact_snapshot_phase", "phase at each contact snapshot (0 before yield, 1 slow front, 2 transient, 3 "
                                          "after arrest) [ns]"},
      {"contacts/contact_snapshots_per_phase", "number of contact snapshots taken in each phase [4]"},
      {"contacts/class_threshold_counts",
       "yield thresholds of the attached contacts summed over the contact snapshots [12, nt] (rows as "
       "class_lifetime_counts, edges threshold_hist_edges); mean_field (continuum at w = 0): expected counts, each "
       "threshold class spread over its quantile interval of g"},
      {"contacts/region_threshold_counts",
       "yield thresholds of the attached contacts at each contact snapshot by region [ns, 3 nt] (behind | tip | ahead, "
       "nt bins each, edges threshold_hist_edges); mean_field (continuum at w = 0): expected counts"},
      {"contacts/threshold_drawn_counts", "every threshold drawn from g (w > 0), on threshold_hist_edges [nt]"},
      {"contacts/detachments_total_per_site", "detachments per site over the whole run [nx] (continuum: expected)"},
      {"contacts/attachments_total_per_site", "attachments per site over the whole run [nx] (continuum: expected)"},
      {"snapshots/t", "time of each snapshot (cadence output.snapshot_dt) [ns]"},
      {"snapshots/A", "contact-area fraction A(x, t) [ns, nx]"},
      {"snapshots/sigma_bar", "interfacial elastic stress sigma_bar(x, t) [ns, nx]"},
      {"snapshots/v", "slip rate v(x, t) [ns, nx]"},
      {"snapshots/u", "slip u(x, t) [ns, nx]"},
      {"snapshots/age",
       "mean contact age a(x, t) of the attached contacts [ns, nx] (output.ages; continuum: M/A of its age mass, "
       "docs/model.md §7.1; agent: exact; NaN where no contact is attached)"},
      {"series/age", "mean contact age of the attached contacts of the single site (0D, output.ages)"},
      {"bulk/t", "time of each bulk snapshot (cadence output.bulk_dt: the first step end at or after each multiple) [nb]"},
      {"bulk/x", "x of the kept columns of the strip (every output.bulk_stride-th node, and the last) [nxk]"},
      {"bulk/y",
       "y of the kept rows of the strip (every output.bulk_stride-th row, and the top): 0 the interface, "
       "bulk.height the top [nyk]"},
      {"bulk/u",
       "displacement at the kept nodes: the antiplane strip's u(x, y, t) [nb, nyk, nxk]; the in-plane strip's "
       "(u_x, u_y) [nb, nyk, nxk, 2]"},
      {"bulk/sigma_xx",
       "in-plane strip: normal stress sigma_xx at the kept nodes, second-order differences on the full grid (central "
       "inside, one-sided on the faces; docs/model.md §10.4) [nb, nyk, nxk]"},
      {"bulk/sigma_yy", "in-plane strip: normal stress sigma_yy at the kept nodes, as sigma_xx [nb, nyk, nxk]"},
      {"bulk/sigma_xy", "in-plane strip: shear stress sigma_xy at the kept nodes, as sigma_xx [nb, nyk, nxk]"},
      {"snapshots/sigma_yy",
       "in-plane strip: interface normal stress sigma_yy(x, 0, t), the reaction that holds u_y = 0 per interface "
       "length (compression negative; docs/model.md §10.4) [ns, nx]"},
      {"series/min_sigma_yy", "in-plane strip: the most compressive interface normal stress, min_x sigma_yy(x, 0, t)"},
      {"series/max_sigma_yy", "in-plane strip: the most tensile interface normal stress, max_x sigma_yy(x, 0, t)"},
      {"bulk/tau_xz",
       "shear stress tau_xz = mu' du/dx (mu' = bulk.mu / bulk.height) at the kept nodes, second-order differences "
       "on the full grid (central inside, one-sided on the faces) [nb, nyk, nxk]"},
      {"bulk/tau_yz",
       "shear stress tau_yz = mu' du/dy (mu' = bulk.mu / bulk.height) at the kept nodes, second-order differences "
       "on the full grid (central inside, one-sided on the faces) [nb, nyk, nxk]"},
      {"cycles/t_start", "spring block stick-slip cycles: time the slip event started (v > measure.v_event)"},
      {"cycles/F_peak", "spring block stick-slip cycles: largest drive force since the previous event (peak friction)"},
      {"cycles/F_residual", "spring block stick-slip cycles: smallest drive force during the event (residual friction)"},
      {"sequence/t_start", "slip event start: max v rose above measure.v_event (docs/model.md §3.2)"},
      {"sequence/t_end", "slip event end: max v fell below measure.arrest_fraction * v_event (NaN: running at t_end)"},
      {"sequence/peak_v", "largest max v during the event"},
      {"sequence/x_arrest", "largest tip position (measure.A_tip) during the event (NaN: no tip)"},
      {"sequence/c_event", "LS slope of the tip over the middle half of its run during the event"},
      {"sequence/spanning", "1 when the tip reached the far end (the whole interface slid), else 0"},
      {"friction_law/v", "imposed slip rate of each sweep point"},
      {"friction_law/sigma", "steady frictional stress: time average of sigma over the last part of the run"},
      {"friction_law/sigma_stderr", "standard error of friction_law/sigma from batch means"},
      {"friction_law/A", "time-averaged contact-area fraction over the same window"},
      {"friction_law/sigma_closed_form", "closed form sigma_ss(v) = alpha/(1 + kappa v) + eta v (docs/model.md §1)"},
  };
  const std::string key = group.empty() ? name : group + "/" + name;
  if (const auto it = known.find(key); it != known.end()) return it->second;
  if (group == "contacts") return "contact statistics '" + name + "' of the agent representation (docs/output.md)";
  return group + " column '" + name + "' (docs/output.md)";
}

std::string group_description(const std::string& group) {
  static const std::map<std::string, std::string> known = {
      {"series", "time series, one sample every output.series_dt"},
      {"snapshots", "fields along the interface, one row every output.snapshot_dt"},
      {"bulk", "the strip's body (bulk.height) on a decimated grid (output.bulk_stride), one snapshot every "
               "output.bulk_dt: the antiplane strip's displacement u and shear stresses tau_xz, tau_yz; the in-plane "
               "strip's displacement (u_x, u_y) and stresses sigma_xx, sigma_yy, sigma_xy"},
      {"events", "event times and front speeds (docs/model.md §3) as attributes; NaN where the run had no such event; "
                 "the _alt names are measured on the measure.A_tip_alt front"},
      {"cycles", "stick-slip cycles of the spring block, one entry per cycle"},
      {"sequence", "slip events of an edge-loaded run (output.sequence), one entry per event, from the series"},
      {"friction_law", "steady friction law of an imposed slip-rate sweep, one entry per slip rate"},
      {"contacts", "contact statistics: measured (agent representation) or predicted from the fields (continuum, "
                   "docs/contacts.md)"},
  };
  const auto it = known.find(group);
  return it == known.end() ? group : it->second;
}

void columns(hid_t model_group, const std::string& model, const std::string& group, const compare::Columns& cols) {
  Hid g = make_group(model_group, group, "/" + model + "/" + group);
  attr_string(g.get(), "description", group_description(group));
  for (const auto& [name, v] : cols)
    dataset_1d(g.get(), name, v, description_of(group, name), "/" + model + "/" + group + "/" + name);
}

void events(hid_t model_group, const std::string& model, const compare::ModelResult& r) {
  Hid g = make_group(model_group, "events", "/" + model + "/events");
  attr_string(g.get(), "description", group_description("events"));
  for (const auto& [name, member] : compare::event_fields) {
    attr_double(g.get(), name, r.events.*member);
    attr_double(g.get(), std::string(name) + "_alt", r.events_alt.*member);
  }
  // Why an event is NaN where a reader could expect a value (docs/output.md).
  for (const auto& [name, why] : r.events.reasons) attr_string(g.get(), name + "_reason", why);
  for (const auto& [name, why] : r.events_alt.reasons) attr_string(g.get(), name + "_alt_reason", why);
}

void model(hid_t file, const compare::ModelResult& r, int deflate) {
  const std::string& m = r.model;
  Hid g = make_group(file, m, "/" + m);
  for (const auto& [name, value] : r.scalars) attr_double(g.get(), name, value);
  for (const auto& [name, value] : r.labels) attr_string(g.get(), name, value);
  attr_status(g.get(), r.status);
  attr_string(g.get(), "message", r.message);
  attr_double(g.get(), "wall_seconds", r.wall_seconds);

  dataset_1d(g.get(), "x", r.x, description_of("", "x"), "/" + m + "/x");
  columns(g.get(), m, "series", r.series);

  if (!r.snapshot_t.empty()) {
    Hid s = make_group(g.get(), "snapshots", "/" + m + "/snapshots");
    attr_string(s.get(), "description", group_description("snapshots"));
    dataset_1d(s.get(), "t", r.snapshot_t, description_of("snapshots", "t"), "/" + m + "/snapshots/t");
    const hsize_t ns = r.snapshot_t.size(), nx = r.x.size();
    for (const auto& [name, v] : r.snapshots) {
      const std::string where = "/" + m + "/snapshots/" + name;
      if (v.size() != ns * nx)
        throw OutputError("snapshot column " + name + " of " + m + " has " + std::to_string(v.size()) +
                          " values, expected ns * nx = " + std::to_string(ns) + " * " + std::to_string(nx));
      dataset(s.get(), name, v.data(), {ns, nx}, description_of("snapshots", name), where, deflate);
    }
  }

  if (!r.bulk_t.empty()) {
    const std::string base = "/" + m + "/bulk";
    Hid b = make_group(g.get(), "bulk", base);
    attr_string(b.get(), "description", group_description("bulk"));
    dataset_1d(b.get(), "t", r.bulk_t, description_of("bulk", "t"), base + "/t");
    dataset_1d(b.get(), "x", r.bulk_x, description_of("bulk", "x"), base + "/x");
    dataset_1d(b.get(), "y", r.bulk_y, description_of("bulk", "y"), base + "/y");
    const hsize_t nb = r.bulk_t.size(), nyk = r.bulk_y.size(), nxk = r.bulk_x.size(), nodes = nb * nyk * nxk;
    for (const auto& [name, v] : r.bulk) {  // a field's values per node, innermost: [nb, nyk, nxk] or [nb, nyk, nxk, nc]
      const std::string where = base + "/" + name;
      if (nodes == 0 || v.empty() || v.size() % nodes != 0)
        throw OutputError("bulk snapshot field " + name + " of " + m + " has " + std::to_string(v.size()) +
                          " values, expected a multiple of nb * nyk * nxk = " + std::to_string(nb) + " * " +
                          std::to_string(nyk) + " * " + std::to_string(nxk));
      const hsize_t components = v.size() / nodes;
      std::vector<hsize_t> dims{nb, nyk, nxk};
      if (components > 1) dims.push_back(components);
      dataset(b.get(), name, v.data(), dims, description_of("bulk", name), where, deflate);
    }
  }

  events(g.get(), m, r);
  if (!r.cycles.empty()) columns(g.get(), m, "cycles", r.cycles);
  if (!r.sequence.empty()) columns(g.get(), m, "sequence", r.sequence);
  if (!r.friction_law.empty()) columns(g.get(), m, "friction_law", r.friction_law);

  if (!r.contacts.empty() || !r.contacts_2d.empty()) {
    const std::string base = "/" + m + "/contacts";
    Hid c = make_group(g.get(), "contacts", base);
    attr_string(c.get(), "description", group_description("contacts"));
    for (const auto& [name, v] : r.contacts)
      dataset_1d(c.get(), name, v, description_of("contacts", name), base + "/" + name);
    for (const auto& [name, t] : r.contacts_2d) {
      if (t.cols == 0 || t.data.size() % t.cols != 0)
        throw OutputError("contact table " + name + " of " + m + " has " + std::to_string(t.data.size()) +
                          " values, not a whole number of rows of " + std::to_string(t.cols));
      dataset(c.get(), name, t.data.data(), {t.data.size() / t.cols, t.cols}, description_of("contacts", name),
              base + "/" + name);
    }
  }
}


std::string utc_now_iso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// /meta: provenance of the program and of this run (shared by results.h5 and study.h5).
void write_meta(hid_t file, const RunMeta& meta, compare::RunStatus status, const std::string& message,
                const std::string& scene, const std::string& models) {
  Hid g = make_group(file, "meta", "/meta");
  const LibraryVersions lv = library_versions();
  attr_string(g.get(), "version", build_info::version);
  attr_int(g.get(), "layout_version", layout_version);
  attr_string(g.get(), "git_commit", build_info::git_commit);
  attr_string(g.get(), "compiler", lv.compiler);
  attr_string(g.get(), "hdf5_version", lv.hdf5);
  attr_string(g.get(), "boost_version", lv.boost);
  attr_string(g.get(), "tomlplusplus_version", lv.tomlplusplus);
  attr_string(g.get(), "cli11_version", lv.cli11);
  attr_string(g.get(), "eigen_version", lv.eigen);
  attr_string(g.get(), "created_utc", utc_now_iso8601());
  attr_double(g.get(), "wall_seconds", meta.wall_seconds);
  attr_status(g.get(), status);
  attr_string(g.get(), "command_line", meta.command_line);
  attr_string(g.get(), "message", message);
  attr_string(g.get(), "scene", scene);
  attr_string(g.get(), "models", models);
}

// /compare: every metric a scalar dataset with its definition; the online field distances and the
// friction-law differences as 1D datasets.
void comparison_group(hid_t file, const compare::Comparison& c) {
  Hid g = make_group(file, "compare", "/compare");
  attr_string(g.get(), "description",
              "metrics of the comparison layer (discrete vs " + c.reference + " on the same scene, grid and time step); "
              "each dataset has its definition as the attribute 'definition'");
  if (c.reference != "continuum") attr_string(g.get(), "reference", c.reference);  // (files before mean_field: none)
  auto definition = [&](const std::string& key) {
    const auto it = c.definitions.find(key);
    return it == c.definitions.end() ? key : it->second;
  };
  for (const auto& [name, value] : c.metrics) {
    Hid space(H5Screate(H5S_SCALAR), H5Sclose, "make a scalar dataspace");
    Hid ds(H5Dcreate2(g.get(), name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Dclose, "create dataset /compare/" + name);
    check(H5Dwrite(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value), "write /compare/" + name);
    attr_string(ds.get(), "definition", definition(name));
  }
  for (const auto& [group, cols] : {std::pair<const char*, const compare::Columns*>{"fields", &c.fields},
                                    {"friction_law", &c.friction_law}, {"contacts", &c.contacts}}) {
    if (cols->empty()) continue;
    Hid sub = make_group(g.get(), group, std::string("/compare/") + group);
    for (const auto& [name, v] : *cols) {
      const std::string key = std::string(group) + "/" + name;
      dataset_1d(sub.get(), name, v, definition(key), "/compare/" + key);
      Hid ds(H5Dopen2(sub.get(), name.c_str(), H5P_DEFAULT), H5Dclose, "open /compare/" + key);
      attr_string(ds.get(), "definition", definition(key));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The file is built in memory (HDF5's core driver, no backing store) and written out by us: HDF5
// never writes to the disk, so a full disk or any write error is one failed write(2) that we report
// (a failed H5Fclose on a real file would leave the library with an open file it cannot flush, which
// crashed at exit), and the temporary file is created exclusively without following symbolic links.

// The core driver's buffer (HDF5's file-image callbacks): one reservation of address space, advised for transparent
// huge pages and grown in place, instead of malloc's 4 KiB pages. Every page of the buffer is fresh, and on this
// kind of machine a 4 KiB page fault costs ~2.5 µs (fig1's 5.5 MB image: ~1350 faults, ~3.4 ms); a 2 MiB page
// costs one fault. Mappings are kept in a table (the callbacks' udata is copied with every property list).
namespace image_memory {
constexpr std::size_t kHuge = std::size_t{2} << 20;
std::mutex mutex;
std::map<void*, std::size_t> mappings;  // address -> reserved bytes
std::size_t round_up(std::size_t n) { return (n + kHuge - 1) / kHuge * kHuge; }
void* reserve(std::size_t bytes) {
  const std::size_t len = round_up(std::max(bytes, 4 * kHuge));
  void* p = ::mmap(nullptr, len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p == MAP_FAILED) return nullptr;
  ::madvise(p, len, MADV_HUGEPAGE);  // advice: without it (or without THP) the buffer is ordinary pages
  const std::lock_guard<std::mutex> lock(mutex);
  mappings[p] = len;
  return p;
}
void* image_malloc(std::size_t size, H5FD_file_image_op_t, void*) { return reserve(size); }
void* image_memcpy(void* dest, const void* src, std::size_t size, H5FD_file_image_op_t, void*) {
  return std::memcpy(dest, src, size);
}
void* image_realloc(void* ptr, std::size_t size, H5FD_file_image_op_t, void*) {
  if (ptr == nullptr) return reserve(size);
  std::unique_lock<std::mutex> lock(mutex);
  const auto it = mappings.find(ptr);
  if (it == mappings.end()) return nullptr;
  if (size <= it->second) return ptr;
  const std::size_t len = round_up(std::max(size, 2 * it->second));
  void* q = ::mremap(ptr, it->second, len, MREMAP_MAYMOVE);
  if (q == MAP_FAILED) return nullptr;
  mappings.erase(it);
  mappings[q] = len;
  lock.unlock();
  ::madvise(q, len, MADV_HUGEPAGE);
  return q;
}
herr_t image_free(void* ptr, H5FD_file_image_op_t, void*) {
  if (ptr == nullptr) return 0;
  std::unique_lock<std::mutex> lock(mutex);
  const auto it = mappings.find(ptr);
  if (it == mappings.end()) return -1;
  const std::size_t len = it->second;
  mappings.erase(it);
  lock.unlock();
  return ::munmap(ptr, len) == 0 ? 0 : -1;
}
}  // namespace image_memory

// `checksummed`: the file declares a user block of checksum_block_bytes (HDF5 then starts at that
// offset), which save_image fills with the checksum of the rest (docs/output.md, "Checksum").
Hid create_in_memory(const std::filesystem::path& tmp, bool checksummed = false) {
  Hid fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "make a file access property list");
  // Grown 1 MiB at a time: the driver zeroes every increment it allocates, and a 16 MiB one cost a
  // memset with 4096 page faults (~8 ms) for a 160 kB file.
  check(H5Pset_fapl_core(fapl.get(), 1 << 20, 0), "select the in-memory driver");
  H5FD_file_image_callbacks_t callbacks{image_memory::image_malloc, image_memory::image_memcpy,
                                        image_memory::image_realloc, image_memory::image_free, nullptr, nullptr,
                                        nullptr};
  check(H5Pset_file_image_callbacks(fapl.get(), &callbacks), "set the in-memory driver's allocator");
  Hid fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "make a file creation property list");
  if (checksummed) check(H5Pset_userblock(fcpl.get(), checksum_block_bytes), "declare the user block");
  return Hid(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose, "create " + tmp.string());
}

// The user block the file declares (0: none).
hsize_t user_block_of(hid_t file, const std::filesystem::path& tmp) {
  Hid fcpl(H5Fget_create_plist(file), H5Pclose, "read the creation properties of " + tmp.string());
  hsize_t size = 0;
  check(H5Pget_userblock(fcpl.get(), &size), "read the user block size of " + tmp.string());
  return size;
}

std::string errno_text(int e) { return std::strerror(e); }

// Writes the whole image to `tmp`, created exclusively (O_EXCL | O_NOFOLLOW: a planted file or
// symbolic link is never opened, let alone truncated), flushed to the disk before it is renamed.
void write_image_file(const std::filesystem::path& tmp, std::span<const char> image) {
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError("cannot create " + tmp.string() + ": " + errno_text(errno));
  const char* p = image.data();
  std::size_t left = image.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, std::min<std::size_t>(left, std::size_t{1} << 30));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : ENOSPC;
      ::close(fd);
      throw OutputError("cannot write " + tmp.string() + ": " + errno_text(e));
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {  // (EINVAL: a file system without fsync)
    const int e = errno;
    ::close(fd);
    throw OutputError("cannot flush " + tmp.string() + " to the disk: " + errno_text(e));
  }
  if (::close(fd) != 0) throw OutputError("cannot close " + tmp.string() + ": " + errno_text(errno));
}

// The in-memory file written to `tmp` from the driver's own buffer (no copy of the image: for fig1's 5.5 MB that copy
// cost ~1400 page faults and a memcpy, docs/performance.md §14). The core driver holds the file from address 0, any
// user block included (HDF5 never writes it); a file created checksummed gets the checksum of the rest, the image
// H5Fget_file_image would return, written into its user block (checksum_block).
void save_image(Hid& file, const std::filesystem::path& tmp) {
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush the file image of " + tmp.string());
  const auto block = static_cast<std::size_t>(user_block_of(file.get(), tmp));
  if (block != 0 && block != checksum_block_bytes)
    throw OutputError("HDF5: unexpected user block of " + std::to_string(block) + " bytes in " + tmp.string());
  const ssize_t size = H5Fget_file_image(file.get(), nullptr, 0);
  if (size < 0) throw OutputError("HDF5: cannot get the file image of " + tmp.string());
  void* handle = nullptr;  // the core driver's handle: the address of its buffer pointer
  check(H5Fget_vfd_handle(file.get(), H5P_DEFAULT, &handle), "get the in-memory buffer of " + tmp.string());
  char* mem = handle ? *static_cast<char**>(handle) : nullptr;
  if (mem == nullptr) throw OutputError("HDF5: no in-memory buffer for " + tmp.string());
  if (block != 0) {
    const std::string b = checksum_block({mem + block, static_cast<std::size_t>(size)});
    std::copy(b.begin(), b.end(), mem);
  }
  write_image_file(tmp, {mem, block + static_cast<std::size_t>(size)});
  file.close("close the in-memory file " + tmp.string());
}

// A normal-load profile's provenance (docs/model.md §12): p(x)/p_0 and the resting area at the model's nodes.
void put_normal_load(hid_t file, const compare::Scene& scene, const compare::ModelResult& r) {
  if (!scene.interface.has_load_profile() || r.x.empty()) return;
  std::vector<double> p(r.x.size()), rest(r.x.size());
  for (std::size_t i = 0; i < r.x.size(); ++i) {
    p[i] = scene.interface.load_at(r.x[i]);
    rest[i] = scene.interface.resting_area_at(r.x[i]);
  }
  const std::string m = "/" + r.model;
  Hid g(H5Gopen2(file, r.model.c_str(), H5P_DEFAULT), H5Gclose, "open " + m);
  dataset_1d(g.get(), "normal_load", p, description_of("", "normal_load"), m + "/normal_load");
  dataset_1d(g.get(), "resting_area", rest, description_of("", "resting_area"), m + "/resting_area");
}

void write_file(const std::filesystem::path& tmp, const compare::Scene& scene, const std::string& resolved_toml,
                const std::vector<compare::ModelResult>& results, const RunMeta& meta,
                const compare::Comparison* comparison) {
  Hid file = create_in_memory(tmp, /*checksummed=*/true);
  std::string message = meta.message;
  if (message.empty())
    for (const auto& r : results)
      if (!r.message.empty()) message += (message.empty() ? "" : "; ") + r.model + ": " + r.message;
  std::string models;
  for (const auto& r : results) models += (models.empty() ? "" : ",") + r.model;
  write_meta(file.get(), meta, overall_status(results, meta.status), message, scene.name, models);
  {
    Hid g(H5Gopen2(file.get(), "meta", H5P_DEFAULT), H5Gclose, "open /meta");
    attr_string(g.get(), "config_hash", config_hash(resolved_toml));
  }
  {
    Hid g = make_group(file.get(), "config", "/config");
    attr_string(g.get(), "toml", resolved_toml);
  }
  for (const auto& r : results) {
    model(file.get(), r, scene.output.deflate);
    put_normal_load(file.get(), scene, r);
  }
  if (comparison && !comparison->empty()) comparison_group(file.get(), *comparison);
  save_image(file, tmp);
}

void write_study_file(const std::filesystem::path& tmp, const compare::StudySpec& spec, const std::string& spec_toml,
                      const std::vector<compare::StudyRun>& runs, const studies::StudyReport& report,
                      const RunMeta& meta, const StudyExecution& exec) {
  Hid file = create_in_memory(tmp, /*checksummed=*/true);
  write_meta(file.get(), meta, meta.status, meta.message, spec.name, "");
  Hid g = make_group(file.get(), "study", "/study");
  attr_string(g.get(), "name", spec.name);
  attr_string(g.get(), "kind", spec.kind);
  attr_string(g.get(), "description", spec.description);
  attr_string(g.get(), "toml", spec_toml);
  std::string notes;
  for (const auto& n : report.notes) notes += n + "\n";
  attr_string(g.get(), "notes", notes);
  {
    Hid sc = make_group(g.get(), "scalars", "/study/scalars");
    attr_string(sc.get(), "description", "fitted rates and summary numbers; each has a definition in /study/definitions");
    for (const auto& [name, value] : report.scalars) attr_double(sc.get(), name, value);
  }
  {
    Hid d = make_group(g.get(), "definitions", "/study/definitions");
    for (const auto& [name, text] : report.definitions) {
      std::string key = name;
      std::replace(key.begin(), key.end(), '/', '.');
      attr_string(d.get(), key, text);
    }
  }
  {
    Hid t = make_group(g.get(), "tables", "/study/tables");
    for (const auto& [table, cols] : report.tables) {
      Hid tg = make_group(t.get(), table, "/study/tables/" + table);
      for (const auto& [col, v] : cols) {
        const auto def = report.definitions.find(table + "/" + col);
        dataset_1d(tg.get(), col, v, def == report.definitions.end() ? col : def->second,
                   "/study/tables/" + table + "/" + col);
      }
    }
  }
  {
    // The runs: one line each, "id group seed key=value ...", and the file each one wrote.
    Hid r = make_group(g.get(), "runs", "/study/runs");
    std::string lines;
    std::vector<double> seeds;
    for (const auto& run : runs) {
      lines += run.id + " group=" + (run.group.empty() ? "-" : run.group) + " seed=" + std::to_string(run.seed);
      for (const auto& [k, v] : run.point) lines += " " + k + "=" + v;
      lines += "\n";
      seeds.push_back(run.seed);
    }
    attr_string(r.get(), "runs", lines);
    attr_string(r.get(), "files", "runs/<id>/results.h5 beside this file");
    dataset_1d(r.get(), "seed", seeds, "discrete.seed of each run, in run order", "/study/runs/seed");
    std::vector<double> skipped(runs.size(), 0.0);
    long long n_skipped = 0;
    for (std::size_t k = 0; k < runs.size() && k < exec.skipped.size(); ++k) {
      skipped[k] = exec.skipped[k];
      n_skipped += exec.skipped[k] != 0;
    }
    dataset_1d(r.get(), "skipped", skipped,
               "1 where the run's results file was complete (status and config hash) from an earlier invocation "
               "and was not rerun, else 0",
               "/study/runs/skipped");
    attr_string(r.get(), "engine", exec.engine);
    attr_int(r.get(), "workers", exec.workers);
    attr_int(r.get(), "skipped", n_skipped);
    attr_int(r.get(), "computed", exec.computed);
    std::string untrusted;
    for (const auto& u : exec.untrusted) untrusted += u + "\n";
    attr_string(r.get(), "untrusted", untrusted);
  }
  save_image(file, tmp);
}

namespace {

// /branch: the points of the continuation in σ_d, one dataset per quantity, and the outcome's scalars and labels.
void put_fronts_branch(hid_t file, const compare::FrontsResult& fr) {
  static const std::map<std::string, std::string> branch_desc = {
      {"sigma_d", "applied stress of each continuation point"},
      {"c", "steady front speed"},
      {"v_tip", "slip rate at the tip (closed form of the stuck region ahead)"},
      {"v_behind", "slip rate far behind: sigma_ss(v_behind) = sigma_d on the strengthening branch"},
      {"area_behind", "contact area far behind, 1/(1 + kappa v_behind)"},
      {"overstress_margin", "min over the sliding region of |sigma|/A - 1 (<= 0 would be re-sticking)"},
      {"min_slip_rate", "min slip rate over the profile"},
      {"stable_eigenvalue", "decaying eigenvalue of the sliding state behind (-> 0 at the saddle-node end)"},
      {"residual_norm", "max-norm of the discrete traveling-wave equations at the solution"},
      {"speed_error", "estimated error of c (docs/fronts.md §10.20): the chain's Richardson in xi (4th order); the "
                      "strip's from the front re-solved on every other row (order 1.5 assumed) plus its xi part"}};
  Hid g = make_group(file, "branch", "/branch");
  attr_string(g.get(), "description", "the branch c(sigma_d) of steady fronts by continuation (docs/fronts.md)");
  for (const auto& [k, v] : fr.scalars) attr_double(g.get(), k, v);
  for (const auto& [k, v] : fr.labels) attr_string(g.get(), k, v);
  for (const auto& [name, v] : fr.branch) {
    const auto it = branch_desc.find(name);
    dataset_1d(g.get(), name, v, it == branch_desc.end() ? name : it->second, "/branch/" + name);
  }
}

// /profiles/<k>: the solved fronts on the solver's mesh (the strip's also with its rows and u(ξ, y)).
void put_fronts_profiles(hid_t file, const compare::Scene& scene, const compare::FrontsResult& fr) {
  Hid g = make_group(file, "profiles", "/profiles");
  attr_string(g.get(), "description", "solved fronts on the solver's mesh, tip at xi = 0 (xi = x - c t)");
  for (std::size_t k = 0; k < fr.profiles.size(); ++k) {
    const auto& p = fr.profiles[k];
    const std::string name = std::to_string(k), where = "/profiles/" + name;
    Hid pg = make_group(g.get(), name, where);
    attr_double(pg.get(), "sigma_d", p.sigma_d);
    attr_double(pg.get(), "c", p.c);
    attr_double(pg.get(), "c_error", p.c_error);
    attr_double(pg.get(), "v_tip", p.v_tip);
    attr_double(pg.get(), "v_behind", p.v_behind);
    attr_int(pg.get(), "limiting", p.limiting ? 1 : 0);
    for (const auto& [fname, v] : p.fields) dataset_1d(pg.get(), fname, v, "front profile " + fname, where + "/" + fname);
    if (!p.y.empty()) {  // the strip: rows and the bulk field on xi × y
      const hsize_t nx = p.fields.at("xi").size(), ny = p.y.size();
      dataset_1d(pg.get(), "y", p.y, "rows across the height, y = 0 the interface, y = H the top", where + "/y");
      dataset(pg.get(), "u_xy", p.u_xy.data(), {nx, ny}, "bulk displacement u(xi, y) [xi][y]", where + "/u_xy",
              scene.output.deflate);
      dataset(pg.get(), "lift_xy", p.lift_xy.data(), {nx, ny}, "u(xi, y) - u(xi, 0) [xi][y]", where + "/lift_xy",
              scene.output.deflate);
      if (!p.uy_xy.empty())  // the in-plane strip (docs/fronts.md §11.6): u_xy, lift_xy are u_x's
        dataset(pg.get(), "uy_xy", p.uy_xy.data(), {nx, ny}, "in-plane strip: bulk displacement u_y(xi, y) [xi][y]",
                where + "/uy_xy", scene.output.deflate);
    }
  }
}

// /scaling: the c_min of each varied parameter and the fits of c_min against sqrt(μα/(ηκ)) (with --scaling).
void put_fronts_scaling(hid_t file, const compare::FrontsResult& fr) {
  Hid g = make_group(file, "scaling", "/scaling");
  attr_string(g.get(), "description",
              "minimal front speed c_min varying one of mu, alpha, eta, kappa at a time, against sqrt(mu alpha/(eta kappa))");
  std::string names;
  for (const auto& n : fr.scaling_parameters) names += (names.empty() ? "" : ",") + n;
  attr_string(g.get(), "parameters", names);
  Hid pts = make_group(g.get(), "points", "/scaling/points");
  for (const auto& [name, v] : fr.scaling_points) dataset_1d(pts.get(), name, v, "scaling point " + name, "/scaling/points/" + name);
  Hid fits = make_group(g.get(), "fits", "/scaling/fits");
  attr_string(fits.get(), "description",
              "c_min = prefactor * sqrt(mu alpha/(eta kappa)), least squares through the origin over the points with a "
              "c_min; parameter_index -1: all points; points: fitted, tried: in the fit's sweep (fitted or not); "
              "spread: max relative deviation of a fitted point from the line; NaN: the fit was refused (see refused)");
  std::string refused;  // one line per fit, in the order of the rows: "<parameter>: <why>" or "<parameter>: fitted"
  for (std::size_t k = 0; k < fr.scaling_refused.size(); ++k) {
    const double index = fr.scaling_fits.at("parameter_index")[k];
    const std::string name = index < 0 ? "all" : fr.scaling_parameters[static_cast<std::size_t>(index)];
    refused += name + ": " + (fr.scaling_refused[k].empty() ? std::string("fitted") : fr.scaling_refused[k]) + "\n";
  }
  attr_string(fits.get(), "refused", refused);
  for (const auto& [name, v] : fr.scaling_fits) dataset_1d(fits.get(), name, v, "scaling fit " + name, "/scaling/fits/" + name);
}

}  // namespace

// A checksummed in-memory file with /meta (models "continuum", the scene's config_hash) and /config: the start of
// fronts.h5 and stability.h5.
Hid continuum_file(const std::filesystem::path& tmp, const compare::Scene& scene, const std::string& resolved_toml,
                   const RunMeta& meta) {
  Hid file = create_in_memory(tmp, /*checksummed=*/true);
  write_meta(file.get(), meta, meta.status, meta.message, scene.name, "continuum");
  {
    Hid g(H5Gopen2(file.get(), "meta", H5P_DEFAULT), H5Gclose, "open /meta");
    attr_string(g.get(), "config_hash", config_hash(resolved_toml));
  }
  {
    Hid g = make_group(file.get(), "config", "/config");
    attr_string(g.get(), "toml", resolved_toml);
  }
  return file;
}

void write_fronts_file(const std::filesystem::path& tmp, const compare::Scene& scene, const std::string& resolved_toml,
                       const compare::FrontsResult& fr, const RunMeta& meta) {
  Hid file = continuum_file(tmp, scene, resolved_toml, meta);
  put_fronts_branch(file.get(), fr);
  put_fronts_profiles(file.get(), scene, fr);
  if (!fr.scaling_points.empty()) put_fronts_scaling(file.get(), fr);
  save_image(file, tmp);
}

// /stability/<group>: one channel's rates over the kH grid and its row check (docs/output.md "stability.h5").
void put_stability_channel(hid_t parent, const StabilityChannel& c) {
  const std::string where = "/stability/" + c.group;
  Hid g = make_group(parent, c.group, where);
  attr_string(g.get(), "label", c.label);
  attr_int(g.get(), "scene", c.scene ? 1 : 0);
  attr_int(g.get(), "coupled", c.params.coupled ? 1 : 0);
  attr_int(g.get(), "instantaneous", c.params.instantaneous ? 1 : 0);
  attr_double(g.get(), "relaxation_length", c.params.relaxation_length);
  attr_double(g.get(), "relaxation_speed", c.params.relaxation_speed);
  attr_double(g.get(), "check_kH", c.check_kh);
  attr_int(g.get(), "converged", c.converged ? 1 : 0);
  auto parts = [](const std::vector<std::complex<double>>& z, bool imag) {
    std::vector<double> v;
    for (const auto s : z) v.push_back(imag ? s.imag() : s.real());
    return v;
  };
  const std::pair<const char*, const std::vector<std::complex<double>>*> sets[] = {
      {"resolved", &c.resolved}, {"fastest", &c.fastest}, {"check", &c.check_fastest}};
  for (const auto& [name, z] : sets)
    for (const bool imag : {false, true}) {
      const std::string n = std::string(name) + (imag ? "_im" : "_re");
      dataset_1d(g.get(), n, parts(*z, imag), std::string(imag ? "Im s" : "Re s") + " of " + name, where + "/" + n);
    }
  dataset_1d(g.get(), "roundoff", c.roundoff, "1e-8 of the largest |s| at each kH (the eigensolver's round-off)",
             where + "/roundoff");
  const std::vector<double> rows(c.check_rows.begin(), c.check_rows.end());
  dataset_1d(g.get(), "check_rows", rows, "rows of the row check (check_re, check_im at check_kH)", where + "/check_rows");
}

void write_stability_file(const std::filesystem::path& tmp, const compare::Scene& scene, const std::string& resolved_toml,
                          const StabilityResult& r, const RunMeta& meta) {
  Hid file = continuum_file(tmp, scene, resolved_toml, meta);
  Hid g = make_group(file.get(), "stability", "/stability");
  attr_string(g.get(), "description",
              "growth rates s of perturbations e^{ikx + st} of homogeneous sliding at v0 on the in-plane strip under the "
              "normal-load coupling (docs/model.md §12.6, §12.7): continuum::leading_growth_rate per channel and kH");
  const auto& p = r.params;
  const double A0 = 1.0 / (1.0 + p.kappa * p.v0);
  const std::pair<const char*, double> scalars[] = {
      {"v0", p.v0}, {"v_m", continuum::steady_minimum_velocity(scene.interface)}, {"normal_load", p.p0},
      {"exponent", p.exponent}, {"coupling_coefficient", p.exponent * p.alpha * A0 / p.p0}, {"height", p.height},
      {"mu_strip", p.mu_p}, {"lambda_strip", p.lambda_p}, {"rho_strip", p.rho_p},
      {"shear_speed", std::sqrt(p.mu_p / p.rho_p)}, {"pressure_speed", std::sqrt((p.lambda_p + 2.0 * p.mu_p) / p.rho_p)},
      {"max_frequency", r.max_frequency}};
  for (const auto& [name, value] : scalars) attr_double(g.get(), name, value);
  attr_int(g.get(), "rows", p.elements);
  for (const auto& c : r.channels)
    if (c.scene) attr_string(g.get(), "scene_channel", c.group);
  dataset_1d(g.get(), "kH", r.kh, "the wavenumbers k H of the grid", "/stability/kH");
  for (const auto& c : r.channels) put_stability_channel(g.get(), c);
  save_image(file, tmp);
}

// Writes through a temporary file renamed onto `path` when complete. Temporary files of processes
// that are gone are removed first; one with this process's own id can only be stale (or planted) and
// is unlinked (unlink removes a symbolic link, never its target).
template <class Write>
void write_atomically(const std::filesystem::path& path, Write&& write) {
  const QuietHdf5 quiet;
  const std::filesystem::path tmp = temporary_path(path);
  const std::filesystem::path dir = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  remove_stale_temporaries(dir, "." + path.filename().string() + ".tmp.");
  ::unlink(tmp.c_str());
  try {
    write(tmp);
    std::filesystem::rename(tmp, path);
  } catch (const std::filesystem::filesystem_error& e) {
    ::unlink(tmp.c_str());
    throw OutputError("cannot move " + tmp.string() + " to " + path.string() + ": " + e.code().message());
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }
}

}  // namespace

compare::RunStatus overall_status(const std::vector<compare::ModelResult>& results, compare::RunStatus floor) {
  for (const auto& r : results) floor = compare::worst(floor, r.status);
  return floor;
}

std::string config_hash(const std::string& resolved_toml) {
  // CRC-64/XZ (ECMA-182 polynomial, reflected, all-ones init and final xor): check value
  // 0x995dc9bbdf1939fa for "123456789".
  boost::crc_optimal<64, 0x42F0E1EBA9EA3693ULL, ~0ULL, ~0ULL, true, true> crc;
  crc.process_bytes(resolved_toml.data(), resolved_toml.size());
  char buf[40];
  std::snprintf(buf, sizeof buf, "crc64-xz:%016llx", static_cast<unsigned long long>(crc.checksum()));
  return buf;
}

std::string checksum_block(std::string_view payload) {
  // Text a person can read with `head -c 512`, then zeros: every byte of the block is what this function
  // writes for the payload, so a reader compares the whole block (apps/h5in.hpp: verify_checksum).
  std::string block = std::string(checksum_magic) + "xxh3-64 " + core::content_hash_hex(payload) + "\nbytes " +
                      std::to_string(payload.size()) + "\n";
  block.resize(checksum_block_bytes, '\0');
  return block;
}

std::size_t remove_stale_temporaries(const std::filesystem::path& dir, const std::string& prefix) {
  std::size_t removed = 0;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(digits);
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to judge)
    struct stat st {};
    if (::lstat(it->path().c_str(), &st) != 0 || st.st_uid != ::geteuid()) continue;
    if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) continue;
    if (::unlink(it->path().c_str()) == 0) ++removed;
  }
  return removed;
}

std::filesystem::path temporary_path(const std::filesystem::path& path) {
  std::string name = ".";
  name += path.filename().string();
  name += ".tmp.";
  name += std::to_string(::getpid());
  return path.parent_path() / name;
}

void write_results(const std::filesystem::path& path, const compare::Scene& scene, const std::string& resolved_toml,
                   const std::vector<compare::ModelResult>& results, const RunMeta& meta,
                   const compare::Comparison* comparison) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    write_file(tmp, scene, resolved_toml, results, meta, comparison);
  });
}

void write_study(const std::filesystem::path& path, const compare::StudySpec& spec, const std::string& spec_toml,
                 const std::vector<compare::StudyRun>& runs, const studies::StudyReport& report, const RunMeta& meta,
                 const StudyExecution& execution) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    write_study_file(tmp, spec, spec_toml, runs, report, meta, execution);
  });
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_image_file(tmp, {text.data(), text.size()}); });
}

void write_fronts(const std::filesystem::path& path, const compare::Scene& scene, const std::string& resolved_toml,
                  const compare::FrontsResult& fronts, const RunMeta& meta) {
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_fronts_file(tmp, scene, resolved_toml, fronts, meta); });
}

void write_stability(const std::filesystem::path& path, const compare::Scene& scene, const std::string& resolved_toml,
                     const StabilityResult& result, const RunMeta& meta) {
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_stability_file(tmp, scene, resolved_toml, result, meta); });
}

LibraryVersions library_versions() {
  LibraryVersions v;
#if defined(__clang__)
  v.compiler = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  v.compiler = std::string("GCC ") + __VERSION__;
#else
  v.compiler = "unknown";
#endif
  unsigned maj = 0, min = 0, rel = 0;
  H5get_libversion(&maj, &min, &rel);
  v.hdf5 = std::to_string(maj) + "." + std::to_string(min) + "." + std::to_string(rel);
  v.boost = std::to_string(BOOST_VERSION / 100000) + "." + std::to_string(BOOST_VERSION / 100 % 1000) + "." +
            std::to_string(BOOST_VERSION % 100);
  v.tomlplusplus = std::to_string(TOML_LIB_MAJOR) + "." + std::to_string(TOML_LIB_MINOR) + "." +
                   std::to_string(TOML_LIB_PATCH);
  v.cli11 = CLI11_VERSION;
  v.eigen = build_info::eigen_version;
  return v;
}

}  // namespace slipfront::app
