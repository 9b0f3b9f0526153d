// slipfront._slipfront: one model of a scene run in this process (docs/python.md, "In-process: Simulation").
// The run is the program's own: the scene is parsed and validated by app::parse_scene, the model's law and
// stepper are chosen as compare::run_scene/run_model choose them, and it is compare::DynamicRun (a bulk scene)
// or compare::ImposedHistory (an imposed slip-rate history) stepped one step at a time as compare::run_loop
// steps it — so advancing to the end gives the program's run bit for bit. Checkpoints are the bytes of the
// program's checkpoint files (apps/checkpoint.hpp), of the scene with this model alone.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/build_info.hpp"
#include "apps/checkpoint.hpp"
#include "apps/config.hpp"
#include "compare/laws.hpp"
#include "compare/runner.hpp"
#include "core/archive.hpp"

namespace py = pybind11;
using namespace slipfront;

namespace {

// The fields a Simulation shows, in this order (names as in docs/output.md snapshots/).
constexpr std::array<const char*, 5> field_names = {"x", "u", "v", "A", "sigma_bar"};

// One model's run, whatever its law and stepper.
struct Run {
  virtual ~Run() = default;
  virtual bool done() const = 0;
  virtual void step() = 0;
  virtual double time() const = 0;
  virtual double end() const = 0;
  virtual void fields(std::array<std::vector<double>, 5>& out) const = 0;  // field_names
  virtual std::string state() = 0;                                        // for a checkpoint
  virtual void restore(core::Archive& ar) = 0;
  virtual compare::ModelResult finish() = 0;
};

void copy_into(std::vector<double>& out, std::span<const double> in) { out.assign(in.begin(), in.end()); }

template <class Law, class Stepper>
struct BulkRun final : Run {
  compare::DynamicRun<Law, Stepper> run;
  BulkRun(const compare::Scene& s, Law law, const std::string& model)
      : run(s, std::move(law), model, compare::contact_prediction_for(s, model)) {}
  bool done() const override { return run.done(); }
  void step() override { run.step(); }
  double time() const override { return run.time(); }
  double end() const override { return run.end(); }
  void fields(std::array<std::vector<double>, 5>& out) const override {
    copy_into(out[0], run.sim().bulk().x());
    copy_into(out[1], run.sim().slip());
    copy_into(out[2], run.sim().slip_rate());
    copy_into(out[3], run.sim().law().contact_area());
    copy_into(out[4], run.sim().law().sigma_bar());
  }
  // What compare::run_scene checkpoints for a scene of this model alone: no model finished, then the run.
  std::string state() override {
    core::Archive ar = core::Archive::writer();
    ar.tag("sequential");
    std::vector<compare::ModelResult> finished;
    ar(finished, run);
    return ar.data();
  }
  void restore(core::Archive& ar) override {
    ar.tag("sequential");
    std::vector<compare::ModelResult> finished;
    ar(finished);
    if (!finished.empty()) throw core::ArchiveError("the checkpoint is of a scene with more than one model");
    ar(run);
  }
  compare::ModelResult finish() override { return run.finish(); }
};

template <class Law>
struct HistoryRun final : Run {
  compare::ImposedHistory<Law> run;
  const compare::Scene& s;
  std::size_t segment = 0;
  HistoryRun(const compare::Scene& scene, Law law, const std::string& model) : run(scene, std::move(law), model), s(scene) {}
  bool done() const override { return run.done(); }
  void step() override { run.step(); }
  double time() const override { return run.time(); }
  double end() const override { return run.end(); }
  void fields(std::array<std::vector<double>, 5>& out) const override {
    out[0] = {0.0};
    out[1] = {std::nan("")};  // no slip: the rate is imposed
    out[2] = {imposed_rate()};
    copy_into(out[3], run.law().contact_area());
    copy_into(out[4], run.law().sigma_bar());
  }
  double imposed_rate() const {  // v(t) of the piecewise-constant history at the current time
    std::size_t k = 0;
    while (k + 1 < s.drive.v.size() && s.drive.v_times[k + 1] <= run.time()) ++k;
    return s.drive.v[k];
  }
  std::string state() override { throw std::invalid_argument("an imposed-rate run has no checkpoints (a 0D run takes seconds)"); }
  void restore(core::Archive&) override { state(); }
  compare::ModelResult finish() override { return run.finish(); }
};

template <class Law, class MakeLaw>
std::unique_ptr<Run> make_run_of(const compare::Scene& s, MakeLaw make, const std::string& model) {
  if (s.drive.loading == core::Loading::imposed_rate) {
    if (s.drive.sweep_points > 0)
      throw std::invalid_argument("a friction-law sweep (drive.points) is not stepped in time: run it with slipfront.run");
    return std::make_unique<HistoryRun<Law>>(s, make(std::size_t{1}), model);
  }
  return compare::with_integrator(s, [&](auto tag) -> std::unique_ptr<Run> {  // as compare::run_model
    using Stepper = typename decltype(tag)::template stepper<Law>;
    return std::make_unique<BulkRun<Law, Stepper>>(s, make(compare::body_shape(s).sites), model);
  });
}

// The model's law, as compare::run_scene builds it.
std::unique_ptr<Run> make_run(const compare::Scene& s, const std::string& m) {
  return compare::with_model_law(s, m, [&](auto make) {
    using Law = decltype(make(std::size_t{1}));
    return make_run_of<Law>(s, make, m);
  });
}

py::dict result_dict(const compare::ModelResult& r) {
  py::dict events, scalars, labels, series, snapshots;
  for (const auto& f : compare::event_fields) events[f.name] = r.events.*f.member;
  for (const auto& [k, v] : r.scalars) scalars[k.c_str()] = v;
  for (const auto& [k, v] : r.labels) labels[k.c_str()] = v;
  for (const auto& [k, v] : r.series) series[k.c_str()] = py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
  const auto nx = static_cast<py::ssize_t>(r.x.size()), ns = static_cast<py::ssize_t>(r.snapshot_t.size());
  snapshots["t"] = py::array_t<double>(ns, r.snapshot_t.data());
  for (const auto& [k, v] : r.snapshots)  // flat [ns * nx], row-major
    if (nx > 0 && static_cast<py::ssize_t>(v.size()) == ns * nx)
      snapshots[k.c_str()] = py::array_t<double>({ns, nx}, v.data());
  py::dict d;
  d["model"] = r.model;
  d["status"] = compare::to_string(r.status);
  d["message"] = r.message;
  d["events"] = events;
  d["scalars"] = scalars;
  d["labels"] = labels;
  d["series"] = series;
  d["x"] = py::array_t<double>(nx, r.x.data());
  d["snapshots"] = snapshots;
  return d;
}

}  // namespace

/// The Python object: a scene (held here: the run keeps a reference to it), its run, and the field buffers the
/// numpy views show (refreshed after every advance: the steppers swap their own buffers, so views of those would
/// go stale; these are allocated once and never moved).
class Simulation {
 public:
  Simulation(const std::string& toml, const std::string& source, std::vector<std::string> overrides,
             const std::string& model, const std::optional<py::bytes>& checkpoint)
      : model_(model), source_(source) {
    overrides.push_back("models=[\"" + model + "\"]");
    scene_ = std::make_unique<compare::Scene>(app::parse_scene(toml, source, overrides));
    start();
    if (checkpoint) restore(std::string(*checkpoint));
  }

  // Steps until `until` is reached (the first step end at or after it), `steps` steps are taken or the run
  // is done; the GIL is released, and Ctrl-C is polled every 1024 steps (KeyboardInterrupt: the run stops
  // between two steps and can be advanced again). Returns the steps taken.
  std::int64_t advance(std::optional<double> until, std::optional<std::int64_t> steps) {
    usable();
    if (busy_) throw std::runtime_error("advance is already running on this Simulation (in another thread)");
    busy_ = true;
    std::int64_t n = 0;
    bool signalled = false;
    {
      py::gil_scoped_release nogil;
      try {
        while (!run_->done() && (!until || run_->time() < *until) && (!steps || n < *steps)) {
          run_->step();
          if (++n % 1024 == 0) {
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) {
              signalled = true;
              break;
            }
          }
        }
      } catch (...) {
        busy_ = false;
        throw;
      }
    }
    busy_ = false;
    steps_ += n;
    refresh();
    if (signalled) throw py::error_already_set();
    return n;
  }

  // A read-only view of a field's buffer; `self` is its base, so the Simulation lives as long as the view.
  static py::array view(py::object self, const std::string& name) {
    auto& s = self.cast<Simulation&>();
    s.usable();
    for (std::size_t k = 0; k < field_names.size(); ++k)
      if (name == field_names[k]) {
        auto& f = s.fields_[k];
        py::array a(py::dtype::of<double>(), {static_cast<py::ssize_t>(f.size())}, {sizeof(double)}, f.data(), self);
        a.attr("setflags")(py::arg("write") = false);
        return a;
      }
    throw py::key_error("no field '" + name + "' (x, u, v, A, sigma_bar)");
  }

  // An imposed-rate scene's history v(t): piecewise constant, rates[k] from times[k] (times[0] = 0, increasing),
  // before the first step. Validated as the scene's drive.v and drive.switch_times are; the resolved
  // configuration (and a checkpoint's) then holds it.
  void set_drive_history(const std::vector<double>& times, const std::vector<double>& rates) {
    usable();
    if (scene_->drive.loading != core::Loading::imposed_rate)
      throw std::invalid_argument("a drive history needs drive.loading = \"imposed_rate\"");
    if (steps_ != 0) throw std::invalid_argument("set the drive history before the first advance");
    compare::Scene s = *scene_;
    s.drive.v = rates;
    s.drive.v_times = times;
    s.drive.sweep_points = 0;
    // the program's own checks, by the key names of the file: the history goes through the TOML
    std::string text = app::to_toml(s);
    *scene_ = app::parse_scene(text, source_, {});
    start();
  }

  py::bytes checkpoint() {
    usable();
    return py::bytes(app::checkpoint_bytes(resolved_, run_->time(), run_->state()));
  }

  py::dict result() {
    usable();
    py::dict d = result_dict(run_->finish());
    run_.reset();  // finish() hands the run's result over: nothing is left to advance
    closed_ = "its result() was taken";
    return d;
  }

  void close() {
    run_.reset();
    if (closed_.empty()) closed_ = "it was closed";
  }

  double time() const { return usable(), run_->time(); }
  double end() const { return usable(), run_->end(); }
  bool done() const { return usable(), run_->done(); }
  std::int64_t steps() const { return steps_; }
  const std::string& resolved() const { return resolved_; }
  const std::string& model() const { return model_; }
  bool closed() const { return !closed_.empty(); }

 private:
  void start() {
    resolved_ = app::to_toml(*scene_);
    run_ = make_run(*scene_, model_);
    if (allocated_) return refresh();  // a new history: the same sizes, the buffers (and views of them) kept
    run_->fields(fields_);
    for (std::size_t k = 0; k < fields_.size(); ++k) sizes_[k] = fields_[k].size();
    allocated_ = true;
  }
  void restore(const std::string& bytes) {
    app::Checkpoint c = app::parse_checkpoint(bytes, "the checkpoint");
    if (c.resolved_toml != resolved_)
      throw std::invalid_argument("the checkpoint belongs to another configuration (make the Simulation with the scene, "
                                  "overrides and model it was made with)");
    core::Archive ar = core::Archive::reader(std::move(c.state));
    run_->restore(ar);
    if (!ar.at_end()) throw core::ArchiveError("the checkpoint has bytes after the run's state");
    refresh();
  }
  // Copies the fields into the buffers in place (their addresses never change: views stay valid).
  void refresh() {
    std::array<std::vector<double>, 5> now;
    run_->fields(now);
    for (std::size_t k = 0; k < fields_.size(); ++k) {
      if (now[k].size() != sizes_[k]) throw std::logic_error("a field changed its size");
      std::copy(now[k].begin(), now[k].end(), fields_[k].begin());
    }
  }
  const Simulation& usable() const {
    if (!closed_.empty()) throw std::invalid_argument("this Simulation is gone: " + closed_);
    return *this;
  }

  std::string model_, source_, resolved_, closed_;
  std::unique_ptr<compare::Scene> scene_;
  std::unique_ptr<Run> run_;
  std::array<std::vector<double>, 5> fields_;
  std::array<std::size_t, 5> sizes_{};
  std::int64_t steps_ = 0;
  bool busy_ = false, allocated_ = false;
};

PYBIND11_MODULE(_slipfront, m) {
  m.doc() = "slipfront in process: one model of a scene stepped by the program's own run (docs/python.md)";
  m.attr("commit") = app::build_info::git_commit;
  py::register_exception<app::ConfigError>(m, "ConfigError", PyExc_ValueError);
  py::register_exception<app::CheckpointError>(m, "CheckpointError", PyExc_ValueError);
  py::register_exception<core::ArchiveError>(m, "ArchiveError", PyExc_ValueError);
  py::class_<Simulation>(m, "_Simulation")
      .def(py::init<const std::string&, const std::string&, std::vector<std::string>, const std::string&,
                    const std::optional<py::bytes>&>(),
           py::arg("toml"), py::arg("source"), py::arg("overrides"), py::arg("model"), py::arg("checkpoint") = py::none())
      .def("advance", &Simulation::advance, py::arg("until") = py::none(), py::arg("steps") = py::none())
      .def("view", &Simulation::view, py::arg("name"))
      .def("set_drive_history", &Simulation::set_drive_history, py::arg("times"), py::arg("rates"))
      .def("checkpoint", &Simulation::checkpoint)
      .def("result", &Simulation::result)
      .def("close", &Simulation::close)
      .def_property_readonly("time", &Simulation::time)
      .def_property_readonly("t_end", &Simulation::end)
      .def_property_readonly("done", &Simulation::done)
      .def_property_readonly("steps", &Simulation::steps)
      .def_property_readonly("closed", &Simulation::closed)
      .def_property_readonly("model", &Simulation::model)
      .def_property_readonly("resolved_toml", &Simulation::resolved);
}
