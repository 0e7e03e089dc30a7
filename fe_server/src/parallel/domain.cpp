#include "parallel/domain.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <ctime>

#ifdef PCS_HAVE_MPI
#include <mpi.h>
#endif

namespace fe {

namespace {
Domain g_world;
bool g_mpi_started = false;

// mpirun (Open MPI), and srun with PMIx or PMI-2, put these in each rank's
// environment; a process started by hand has none of them.
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}
}  // namespace

int Domain::launched_ranks() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "SLURM_STEP_NUM_TASKS"})
    if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
  return 1;
}

bool Domain::built_with_mpi() {
#ifdef PCS_HAVE_MPI
  return true;
#else
  return false;
#endif
}

void Domain::init(int* argc, char*** argv) {
#ifdef PCS_HAVE_MPI
  if (!launched_by_mpi()) return;
  int provided = 0;
  // Only the main thread calls MPI (the element threads never do).
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_mpi_started = true;
  // A failed collective ends the run with a message rather than a hang.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_world.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &g_world.size_);
#else
  (void)argc;
  (void)argv;
#endif
}

void Domain::finalize() {
#ifdef PCS_HAVE_MPI
  if (g_mpi_started) {
    g_mpi_started = false;
    MPI_Finalize();
  }
#endif
}

const Domain& Domain::world() { return g_world; }

const Domain& Domain::serial() {
  static const Domain one;
  return one;
}

void Domain::allgather(const double* mine, size_t n, double* all) const {
  if (!parallel()) {
    std::memcpy(all, mine, n * sizeof(double));
    return;
  }
#ifdef PCS_HAVE_MPI
  MPI_Allgather(mine, static_cast<int>(n), MPI_DOUBLE, all, static_cast<int>(n), MPI_DOUBLE, MPI_COMM_WORLD);
#endif
}

void Domain::sum_in_rank_order(std::vector<double>& row, std::vector<double>& all) const {
  const size_t n = row.size(), ranks = static_cast<size_t>(size_);
  all.resize(n * ranks);
  allgather(row.data(), n, all.data());
  for (size_t j = 0; j < n; ++j) {
    double sum = all[j];
    for (size_t r = 1; r < ranks; ++r) sum += all[r * n + j];
    row[j] = sum;
  }
}

void Domain::broadcast(void* data, size_t bytes, int root) const {
  if (!parallel()) return;
#ifdef PCS_HAVE_MPI
  MPI_Bcast(data, static_cast<int>(bytes), MPI_BYTE, root, MPI_COMM_WORLD);
#else
  (void)data, (void)bytes, (void)root;
#endif
}

void Domain::broadcast_waiting(void* data, size_t bytes) const {
  if (!parallel()) return;
#ifdef PCS_HAVE_MPI
  MPI_Request req;
  MPI_Ibcast(data, static_cast<int>(bytes), MPI_BYTE, 0, MPI_COMM_WORLD, &req);
  int done = 0;
  // Naps from 20 µs (below a coupling step's round trip, 65–70 µs on
  // loopback: bench/RESULTS.md), doubling to 1 ms while the wait goes on:
  // the answer comes at most about the time already waited late, and a
  // rank idle while the host waits wakes a thousand times a second, not
  // fifty thousand (measured: 22 % of a core with fixed 20 µs naps).
  long nap_ns = 20000;
  for (;;) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) break;
    const timespec nap{0, nap_ns};
    nanosleep(&nap, nullptr);
    nap_ns = std::min(2 * nap_ns, 1000000L);
  }
#else
  (void)data, (void)bytes;
#endif
}

bool Domain::any(bool mine) const {
  if (!parallel()) return mine;
#ifdef PCS_HAVE_MPI
  int in = mine ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return out != 0;
#else
  return mine;
#endif
}

void Domain::sum_at_root(double* data, size_t n) const {
  if (!parallel()) return;
#ifdef PCS_HAVE_MPI
  if (rank_ == 0)
    MPI_Reduce(MPI_IN_PLACE, data, static_cast<int>(n), MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  else
    MPI_Reduce(data, nullptr, static_cast<int>(n), MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
#else
  (void)data, (void)n;
#endif
}

void Domain::exchange(const std::vector<int>& peers, const std::vector<std::vector<double>>& send,
                      std::vector<std::vector<double>>& recv) const {
  if (!parallel() || peers.empty()) return;
#ifdef PCS_HAVE_MPI
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<MPI_Request> req(2 * peers.size());
  for (size_t k = 0; k < peers.size(); ++k) {
    MPI_Irecv(recv[k].data(), static_cast<int>(recv[k].size()), MPI_DOUBLE, peers[k], 7, MPI_COMM_WORLD, &req[k]);
    MPI_Isend(send[k].data(), static_cast<int>(send[k].size()), MPI_DOUBLE, peers[k], 7, MPI_COMM_WORLD,
              &req[peers.size() + k]);
    traffic_.messages += 1;
    traffic_.bytes += send[k].size() * sizeof(double);
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  traffic_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
#else
  (void)send, (void)recv;
#endif
}

void Domain::abort(int code) const {
#ifdef PCS_HAVE_MPI
  if (parallel()) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace fe
