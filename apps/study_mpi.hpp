#pragma once
// The MPI side of `slipfront study`: detects whether mpirun started this process and loads the MPI
// engine module (apps/mpi_engine.h) with dlopen. Nothing here links MPI: a slipfront built without
// MPI, or run where libmpi is not installed, never touches it unless started by mpirun.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "apps/mpi_engine.h"

namespace slipfront::app {

/// The number of processes mpirun started, from the launcher's environment (Open MPI:
/// OMPI_COMM_WORLD_SIZE; MPICH/Hydra and Intel MPI: PMI_SIZE); 0 when not started by mpirun.
int mpirun_size();

/// One loaded and initialised MPI engine. Every call is serialised by a mutex, so threads of one
/// rank may share it (MPI_THREAD_SERIALIZED).
class MpiEngine {
 public:
  /// dlopen the first module of mpi_engine_candidates() that loads, then MPI_Init. On failure
  /// returns null and says why in `why` (every path tried and its dlerror).
  static std::unique_ptr<MpiEngine> load(std::string& why);
  ~MpiEngine();  ///< finalizes, unless finalize() was called or a collective timed out
  MpiEngine(const MpiEngine&) = delete;
  MpiEngine& operator=(const MpiEngine&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool serialized() const { return serialized_; }  ///< several threads may call (one at a time)
  std::string module_path() const { return path_; }
  std::string library_version() const;

  /// Adds delta to counter `slot` at rank 0; returns the value before. Throws on an MPI error.
  long long fetch_add(int slot, long long delta);
  /// Like fetch_add(slot, 0), but returns -1 at once if another thread holds the engine.
  long long try_read(int slot);
  /// From rank 0 to every rank; false on timeout (seconds, < 0: none). Throws on an MPI error.
  bool broadcast(void* data, std::size_t bytes, double timeout);
  /// Element-wise sum over the ranks; false on timeout. Throws on an MPI error.
  bool sum(std::vector<long long>& values, double timeout);
  void progress();
  /// Finalizes MPI (once). After a timed-out collective MPI cannot be finalized: does nothing then.
  void finalize();

 private:
  MpiEngine() = default;
  const slipfront_mpi_engine* api_ = nullptr;
  std::string path_;
  int rank_ = 0, size_ = 1;
  bool serialized_ = false, finalized_ = false, abandoned_ = false;
  std::mutex mutex_;
};

}  // namespace slipfront::app
