/* The MPI engine of `slipfront study` (interface and purpose: mpi_engine.h). Built only when CMake
 * finds MPI, as a module loaded at run time; plain C against the MPI C API. */
#include "mpi_engine.h"

#include <mpi.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static MPI_Win counters_win = MPI_WIN_NULL;
static long long* counters = NULL;
static int world_rank = 0;

static void set_error(char* error, int size, const char* what, int rc) {
  char text[MPI_MAX_ERROR_STRING] = "";
  int len = 0;
  MPI_Error_string(rc, text, &len);
  snprintf(error, (size_t)size, "%s: %s", what, text);
}

static int engine_init(int* rank, int* size, int* serialized, char* error, int error_size) {
  int provided = MPI_THREAD_SINGLE, rc = MPI_Init_thread(NULL, NULL, MPI_THREAD_SERIALIZED, &provided);
  if (rc != MPI_SUCCESS) {
    snprintf(error, (size_t)error_size, "MPI_Init_thread failed (%d)", rc);
    return 1;
  }
  /* Errors come back as codes, not as an abort of the whole job. */
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
  MPI_Comm_size(MPI_COMM_WORLD, size);
  *rank = world_rank;
  *serialized = provided >= MPI_THREAD_SERIALIZED;
  /* Only rank 0 holds the counters; MPI_Win_allocate lets Open MPI use shared-memory atomics on one node. */
  const MPI_Aint bytes = world_rank == 0 ? (MPI_Aint)(slipfront_mpi_slots * sizeof(long long)) : 0;
  rc = MPI_Win_allocate(bytes, (int)sizeof(long long), MPI_INFO_NULL, MPI_COMM_WORLD, &counters, &counters_win);
  if (rc != MPI_SUCCESS) {
    set_error(error, error_size, "MPI_Win_allocate", rc);
    return 1;
  }
  MPI_Win_set_errhandler(counters_win, MPI_ERRORS_RETURN);
  if (world_rank == 0) {
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, counters_win);
    for (int k = 0; k < slipfront_mpi_slots; ++k) counters[k] = 0;
    MPI_Win_unlock(0, counters_win);
  }
  rc = MPI_Barrier(MPI_COMM_WORLD); /* nobody touches the counters before they are zero */
  if (rc != MPI_SUCCESS) {
    set_error(error, error_size, "MPI_Barrier", rc);
    return 1;
  }
  return 0;
}

static long long engine_fetch_add(int slot, long long delta) {
  if (slot < 0 || slot >= slipfront_mpi_slots || counters_win == MPI_WIN_NULL) return -1;
  long long before = -1;
  if (MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, counters_win) != MPI_SUCCESS) return -1;
  const int rc = MPI_Fetch_and_op(&delta, &before, MPI_LONG_LONG, 0, (MPI_Aint)slot, MPI_SUM, counters_win);
  if (MPI_Win_unlock(0, counters_win) != MPI_SUCCESS || rc != MPI_SUCCESS) return -1;
  return before;
}

/* Waits for `request` with 1 ms sleeps (a blocking MPI call would spin a core at 100%). */
static int wait_sleeping(MPI_Request* request, double timeout) {
  const double start = MPI_Wtime();
  const struct timespec nap = {0, 1000000};
  for (;;) {
    int done = 0;
    if (MPI_Test(request, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) return -1;
    if (done) return 0;
    if (timeout >= 0 && MPI_Wtime() - start > timeout) return 1;
    nanosleep(&nap, NULL);
  }
}

static int engine_broadcast(void* data, long long bytes, double timeout) {
  if (bytes < 0 || bytes > 2147483647LL) return -1;
  MPI_Request request;
  if (MPI_Ibcast(data, (int)bytes, MPI_BYTE, 0, MPI_COMM_WORLD, &request) != MPI_SUCCESS) return -1;
  return wait_sleeping(&request, timeout);
}

static int engine_sum(long long* values, int n, double timeout) {
  MPI_Request request;
  if (MPI_Iallreduce(MPI_IN_PLACE, values, n, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD, &request) != MPI_SUCCESS)
    return -1;
  return wait_sleeping(&request, timeout);
}

static void engine_progress(void) {
  int flag = 0;
  MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
}

static void engine_finalize(void) {
  if (counters_win != MPI_WIN_NULL) MPI_Win_free(&counters_win);
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

static void engine_library_version(char* buf, int size) {
  char text[MPI_MAX_LIBRARY_VERSION_STRING] = "";
  int len = 0;
  MPI_Get_library_version(text, &len);
  text[strcspn(text, "\n")] = '\0';
  snprintf(buf, (size_t)size, "%s", text);
}

const slipfront_mpi_engine* slipfront_mpi_engine_v1(void) {
  static const slipfront_mpi_engine engine = {
      SLIPFRONT_MPI_ENGINE_ABI, engine_init,     engine_fetch_add, engine_broadcast, engine_sum,
      engine_progress,          engine_finalize, engine_library_version,
  };
  return &engine;
}
