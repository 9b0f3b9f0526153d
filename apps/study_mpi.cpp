#include "apps/study_mpi.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>

#include "apps/paths.hpp"

namespace slipfront::app {

int mpirun_size() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(var); v && *v) {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  return 0;
}

std::unique_ptr<MpiEngine> MpiEngine::load(std::string& why) {
  why.clear();
  const auto candidates = mpi_engine_candidates();
  if (candidates.empty()) why = "the executable's path is unknown";
  for (const auto& p : candidates) {
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) {
      why += (why.empty() ? "" : "; ") + p.string() + ": no such file";
      continue;
    }
    // RTLD_GLOBAL: Open MPI's own plugins resolve libmpi's symbols globally.
    void* handle = ::dlopen(p.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (!handle) {
      const char* e = ::dlerror();
      why += (why.empty() ? "" : "; ") + p.string() + ": " + (e ? e : "dlopen failed");
      continue;
    }
    auto entry = reinterpret_cast<slipfront_mpi_engine_entry>(::dlsym(handle, "slipfront_mpi_engine_v1"));
    const slipfront_mpi_engine* api = entry ? entry() : nullptr;
    if (!api || api->abi != SLIPFRONT_MPI_ENGINE_ABI) {
      why += (why.empty() ? "" : "; ") + p.string() + ": not a slipfront MPI engine of this version";
      continue;  // left loaded: unloading a library that may have started MPI is not safe
    }
    std::unique_ptr<MpiEngine> e(new MpiEngine);
    e->api_ = api;
    e->path_ = p.string();
    char error[512] = "";
    int serialized = 0;
    if (api->init(&e->rank_, &e->size_, &serialized, error, sizeof error) != 0) {
      why += (why.empty() ? "" : "; ") + p.string() + ": " + error;
      e->finalized_ = true;  // MPI did not start
      return nullptr;
    }
    e->serialized_ = serialized != 0;
    return e;
  }
  return nullptr;
}

MpiEngine::~MpiEngine() { finalize(); }

std::string MpiEngine::library_version() const {
  char buf[256] = "";
  api_->library_version(buf, sizeof buf);
  return buf;
}

long long MpiEngine::fetch_add(int slot, long long delta) {
  const std::lock_guard lock(mutex_);
  const long long v = api_->fetch_add(slot, delta);
  if (v < 0) throw std::runtime_error("MPI: the run counter at rank 0 cannot be reached (MPI_Fetch_and_op failed)");
  return v;
}

long long MpiEngine::try_read(int slot) {
  const std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return -1;
  return api_->fetch_add(slot, 0);
}

bool MpiEngine::broadcast(void* data, std::size_t bytes, double timeout) {
  const std::lock_guard lock(mutex_);
  const int rc = api_->broadcast(data, static_cast<long long>(bytes), timeout);
  if (rc < 0) throw std::runtime_error("MPI: broadcast failed");
  if (rc == 1) abandoned_ = true;
  return rc == 0;
}

bool MpiEngine::sum(std::vector<long long>& values, double timeout) {
  const std::lock_guard lock(mutex_);
  const int rc = api_->sum(values.data(), static_cast<int>(values.size()), timeout);
  if (rc < 0) throw std::runtime_error("MPI: sum over the ranks failed");
  if (rc == 1) abandoned_ = true;
  return rc == 0;
}

void MpiEngine::progress() {
  const std::unique_lock lock(mutex_, std::try_to_lock);
  if (lock.owns_lock()) api_->progress();
}

void MpiEngine::finalize() {
  const std::lock_guard lock(mutex_);
  if (finalized_ || abandoned_) return;
  finalized_ = true;
  api_->finalize();
}

}  // namespace slipfront::app
