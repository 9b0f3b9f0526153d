/* The MPI engine of `slipfront study` and its C interface.
 *
 * apps/mpi_engine.c is built as the module libslipfront_mpi.so when CMake finds MPI; apps/study_mpi.cpp
 * loads it with dlopen only when the process was started by mpirun. The slipfront executable itself
 * never links libmpi: without MPI installed (or built without it) the thread pool runs studies.
 *
 * Everything a study needs from MPI: a counter array at rank 0 that every rank increments atomically
 * (MPI-3 one-sided MPI_Fetch_and_op: the next run to take, runs finished, a stop request), a
 * broadcast and a sum. The collectives wait with short sleeps instead of MPI's busy polling, so an
 * idle rank leaves its core to the ranks still computing. */
#ifndef SLIPFRONT_MPI_ENGINE_H
#define SLIPFRONT_MPI_ENGINE_H

#ifdef __cplusplus
extern "C" {
#endif

#define SLIPFRONT_MPI_ENGINE_ABI 1

/* The counters at rank 0. */
enum { slipfront_mpi_next = 0, slipfront_mpi_finished = 1, slipfront_mpi_stop = 2, slipfront_mpi_slots = 3 };

typedef struct slipfront_mpi_engine {
  int abi; /* SLIPFRONT_MPI_ENGINE_ABI */
  /* MPI_Init_thread (MPI_THREAD_SERIALIZED requested; *serialized = 1 if provided) and the counter
   * window at rank 0, all zero. Returns 0, or nonzero with a message in `error`. */
  int (*init)(int* rank, int* size, int* serialized, char* error, int error_size);
  /* Adds `delta` to counter `slot` at rank 0 atomically; returns the value before (-1 on error). */
  long long (*fetch_add)(int slot, long long delta);
  /* Broadcasts `bytes` bytes at `data` from rank 0 to every rank. Waits at most `timeout` seconds
   * (< 0: no limit). Returns 0, 1 on timeout (the operation is then abandoned), -1 on error. */
  int (*broadcast)(void* data, long long bytes, double timeout);
  /* Element-wise sum of `n` counters over the ranks, the result on every rank; waits as broadcast. */
  int (*sum)(long long* values, int n, double timeout);
  /* Lets MPI progress one-sided operations aimed at this rank (cheap; called while computing). */
  void (*progress)(void);
  /* Frees the window and finalizes MPI. */
  void (*finalize)(void);
  /* MPI_Get_library_version, e.g. "Open MPI v4.1.4, ..." (first line). */
  void (*library_version)(char* buf, int size);
} slipfront_mpi_engine;

typedef const slipfront_mpi_engine* (*slipfront_mpi_engine_entry)(void);

/* The module's one exported symbol. */
#if defined(__GNUC__)
__attribute__((visibility("default")))
#endif
const slipfront_mpi_engine* slipfront_mpi_engine_v1(void);

#ifdef __cplusplus
}
#endif

#endif /* SLIPFRONT_MPI_ENGINE_H */
