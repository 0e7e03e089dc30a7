// fe_server on several MPI ranks: who this process is among them, and the
// few collective operations the solver and the session need.
//
// The decomposition (partition.hpp, solver.hpp): every rank reads the whole
// deck and keeps the whole nodal state; each owns a share of the elements
// and computes only their forces. A node whose force comes from elements on
// several ranks, or that something global reads (contact, the cavity hook,
// a rigid body, a history), is shared: its partial forces are exchanged
// with the ranks that share it and summed in rank order, so every rank
// that holds it holds the same bits and integrates it identically. What
// reads global state (contact, loads, rigid bodies) then runs on every rank
// on identical inputs and needs no communication of its own.
//
// Built without MPI, or started without mpirun/srun, or with one rank,
// everything here is serial and does nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fe {

class Domain {
 public:
  // MPI_Init when the process was started by mpirun or srun (their
  // environment variables say so) and the build has MPI; otherwise serial.
  static void init(int* argc, char*** argv);
  static void finalize();
  // The process's domain (serial before init).
  static const Domain& world();
  // One rank, always (tests, benchmarks, tools).
  static const Domain& serial();
  // Whether this build can run across ranks.
  static bool built_with_mpi();
  // The ranks mpirun or srun started (their environment; 1 without them;
  // SLURM_STEP_NUM_TASKS is srun's, not the batch script's SLURM_NTASKS).
  // A build without MPI started on several refuses: each would run the
  // whole model and write the same files.
  static int launched_ranks();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool parallel() const { return size_ > 1; }

  // Collectives: every rank calls them in the same order. Serial: copies.
  // all[r·n + k] = rank r's mine[k].
  void allgather(const double* mine, size_t n, double* all) const;
  // Every rank's `row` (the same length on all) gathered into `all` (rank r
  // at r·n), then each entry of `row` replaced by its sum over the ranks in
  // rank order: the same bits on every rank, whatever MPI's own reduction
  // order. Serial: row unchanged, all = row.
  void sum_in_rank_order(std::vector<double>& row, std::vector<double>& all) const;
  // data from rank `root` on every rank.
  void broadcast(void* data, size_t bytes, int root = 0) const;
  // broadcast() from rank 0 for a wait of unknown length (the next command
  // of a session, while the host computes): the other ranks poll and sleep
  // instead of spinning, leaving the cores to the host and rank 0. Every
  // rank calls it.
  void broadcast_waiting(void* data, size_t bytes) const;
  // Whether any rank passed true.
  bool any(bool mine) const;
  // Element-wise sum at rank 0 of values each held by one rank (zeros
  // elsewhere): exact whatever order MPI adds them in (x + 0 = x).
  void sum_at_root(double* data, size_t n) const;
  // One round of point-to-point messages: send[k] to peers[k], recv[k]
  // (sized by the caller) from peers[k].
  void exchange(const std::vector<int>& peers, const std::vector<std::vector<double>>& send,
                std::vector<std::vector<double>>& recv) const;
  // Ends every rank (MPI_Abort); serial: std::exit.
  [[noreturn]] void abort(int code) const;

  // Point-to-point traffic of this rank so far (the halo exchange's cost).
  struct Traffic {
    uint64_t messages = 0, bytes = 0;
    double seconds = 0.0;  // wall time inside exchange()
  };
  const Traffic& traffic() const { return traffic_; }

 private:
  int rank_ = 0, size_ = 1;
  mutable Traffic traffic_;
};

}  // namespace fe
