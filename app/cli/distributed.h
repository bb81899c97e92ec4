// `sinew evolve` over MPI (Open MPI's mpirun): one search, rank 0 driving the optimiser and every
// rank, rank 0 included, evaluating a share of each generation on its own threads. Every rank
// builds the problem itself from the same command line (and the same files); rank 0 checks that
// they agree (search::wire::fingerprint) before the first generation. Evaluations are
// deterministic and travel bit for bit (search::wire), so the best point and cost are those of
// `sinew evolve` alone, whatever the number of ranks.
//
// Messages (rank 0 <-> worker): hello (the worker's fingerprint and threads), points (a share of
// a generation, with its id), cancel (that id: the generation was abandoned), results (the
// share's terms, with the id; results of an abandoned id are dropped), stop.
//
// Without MPI at build time, launchedRanks() still sees mpirun's environment, so `sinew evolve`
// under mpirun says this build cannot share the search instead of running N separate searches.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "sinew/core/status.h"
#include "sinew/search/problem.h"
#include "sinew/search/session.h"

namespace sinew::app::distributed {

// The ranks mpirun (or another PMI launcher) started, from the environment, before any MPI call:
// 1 when this process was not started as one of several.
int launchedRanks();
// Ranks on this machine (to share its cores), from the environment; 1 when unknown.
int localRanks();
bool built();  // whether this sinew was built with MPI

struct Ranks {
  int rank = 0;
  int size = 1;
};

// What rank 0 measured of the communication, for the closing line.
struct Traffic {
  long long generations = 0;
  double bytes_sent = 0.0, bytes_received = 0.0;
  double transfer_ms = 0.0;  // inside MPI calls that move data (not waiting for workers)
  double waiting_ms = 0.0;   // after its own share, waiting for the slowest worker
  std::string line(int ranks) const;
};

#if SINEW_HAVE_MPI
// MPI_Init_thread (serialized: rank 0's search thread makes the calls). Fails when the library
// gives less thread support.
Result<Ranks> start();
void finish();         // MPI_Finalize
void abort(int code);  // MPI_Abort: a rank that failed alone must not leave the others waiting

// Rank 0, before the first generation: every worker's problem is this one. The message names
// the first rank that built another.
Status handshake(const Ranks& ranks, const search::Problem& problem);
// Rank 0: the session's evaluator (Session::setEvaluator). `traffic` outlives the session.
search::GenerationEvaluator coordinator(const Ranks& ranks, Traffic* traffic);
// Rank 0, after the search: the workers leave serve().
void stopWorkers(const Ranks& ranks);

// Ranks > 0: sends hello, then evaluates the shares rank 0 sends until it says stop. Returns the
// process's exit code.
int serve(const Ranks& ranks, const search::Problem& problem, int threads);

// A batch over the ranks (`sinew evolve --batch` under mpirun): rank 0 hands out job indices
// 0..jobs-1 to the ranks as they ask, calling `done(job, rank, exit_code)` as each reports one
// finished, until every job is done and every rank told there are no more.
void dispatch(const Ranks& ranks, int jobs,
              const std::function<void(int job, int rank, int exit_code)>& done);
// Ranks > 0: reports the job it finished (-1 at first) and its exit code, and returns the next
// job, or -1 when there are no more.
int nextJob(int finished, int exit_code);
#endif

}  // namespace sinew::app::distributed
