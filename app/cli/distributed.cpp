#include "cli/distributed.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#if SINEW_HAVE_MPI
#include <mpi.h>

#include "sinew/search/wire.h"
#endif

namespace sinew::app::distributed {
namespace {

int envInt(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr ? std::atoi(v) : 0;
}

}  // namespace

int launchedRanks() {
  // Open MPI's mpirun, then the PMI launchers (MPICH's hydra, Slurm's srun).
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (envInt(name) > 0) return envInt(name);
  return 1;
}

int localRanks() {
  const int n = envInt("OMPI_COMM_WORLD_LOCAL_SIZE");
  return n > 0 ? n : 1;
}

bool built() {
  return SINEW_HAVE_MPI != 0;
}

std::string Traffic::line(int ranks) const {
  const double g = static_cast<double>(std::max<long long>(1, generations));
  char text[256];
  std::snprintf(text, sizeof text,
                "distributed over %d ranks: %lld generations; per generation %.1f kB sent, %.1f kB "
                "received, %.2f ms moving them, %.1f ms waiting for the slowest rank",
                ranks, generations, bytes_sent / g / 1e3, bytes_received / g / 1e3, transfer_ms / g,
                waiting_ms / g);
  return text;
}

#if SINEW_HAVE_MPI
namespace wire = sinew::search::wire;

namespace {

using Clock = std::chrono::steady_clock;

enum Tag : int {
  kHello = 1,
  kPoints = 2,
  kCancel = 3,
  kResults = 4,
  kStop = 5,
  kAsk = 6,
  kJob = 7
};

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Waits for a message from `source` with `tag` (either may be MPI_ANY_*) by polling: Open MPI's
// blocking calls spin a core, which an idle worker would take from the evaluations beside it.
MPI_Status waitFor(int source, int tag) {
  MPI_Status status;
  for (int flag = 0;;) {
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &status);
    if (flag != 0) return status;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

// A message of any length from `source` with `tag`, once one has arrived.
wire::Bytes receive(int source, int tag) {
  const MPI_Status probed = waitFor(source, tag);
  int count = 0;
  MPI_Get_count(&probed, MPI_BYTE, &count);
  wire::Bytes bytes(static_cast<size_t>(count));
  MPI_Recv(bytes.data(), count, MPI_BYTE, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return bytes;
}

void send(const wire::Bytes& bytes, int dest, int tag) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD);
}

bool arrived(int source, int tag) {
  int flag = 0;
  MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
  return flag != 0;
}

// Rank r's share of n points: [first, first + count).
std::pair<size_t, size_t> share(size_t n, int rank, int ranks) {
  const size_t first = n * static_cast<size_t>(rank) / static_cast<size_t>(ranks);
  const size_t last = n * static_cast<size_t>(rank + 1) / static_cast<size_t>(ranks);
  return {first, last - first};
}

// One generation from rank 0: the shares out, its own evaluated here, the others' gathered.
class Generation {
 public:
  Generation(const Ranks& ranks, Traffic* traffic, std::uint64_t id)
      : ranks_(ranks), traffic_(traffic), id_(id) {}

  std::vector<search::Evaluation> run(const search::Problem& problem,
                                      const std::vector<std::vector<double>>& points, int threads,
                                      const std::atomic<bool>* cancel, bool record) {
    std::vector<search::Evaluation> results(points.size());
    sendShares(points);
    const auto [first, count] = share(points.size(), 0, ranks_.size);
    const std::vector<std::vector<double>> own(points.begin() + static_cast<long>(first),
                                               points.begin() + static_cast<long>(first + count));
    std::vector<search::Evaluation> mine =
        search::evaluateAll(problem, own, threads, cancel, record);
    std::move(mine.begin(), mine.end(), results.begin() + static_cast<long>(first));
    gather(points.size(), cancel, results);
    ++traffic_->generations;
    return results;
  }

 private:
  void sendShares(const std::vector<std::vector<double>>& points) {
    for (int r = 1; r < ranks_.size; ++r) {
      const auto [first, count] = share(points.size(), r, ranks_.size);
      const wire::Bytes bytes = wire::packPoints(id_, std::span(points).subspan(first, count));
      const auto t0 = Clock::now();
      send(bytes, r, kPoints);
      traffic_->transfer_ms += msSince(t0);
      traffic_->bytes_sent += static_cast<double>(bytes.size());
    }
  }

  // Waits for every worker's share (dropping results of abandoned generations); on a cancel it
  // tells the workers and marks what has not arrived cancelled.
  void gather(size_t n, const std::atomic<bool>* cancel, std::vector<search::Evaluation>& out) {
    std::vector<char> pending(static_cast<size_t>(ranks_.size), 1);
    pending[0] = 0;
    int left = ranks_.size - 1;
    const auto waiting = Clock::now();
    double moving = 0.0;
    while (left > 0) {
      if (cancel != nullptr && cancel->load()) {
        const wire::Bytes id = wire::packPoints(id_, {});
        for (int r = 1; r < ranks_.size; ++r)
          if (pending[static_cast<size_t>(r)]) send(id, r, kCancel);
        break;  // their answers carry this id and are dropped by the next generation
      }
      bool any = false;
      for (int r = 1; r < ranks_.size; ++r) {
        if (!pending[static_cast<size_t>(r)] || !arrived(r, kResults)) continue;
        const auto t0 = Clock::now();
        const wire::Bytes bytes = receive(r, kResults);
        moving += msSince(t0);
        traffic_->bytes_received += static_cast<double>(bytes.size());
        Result<wire::Results> got = wire::unpackResults(bytes);
        if (!got.ok() || got.value().id != id_) continue;  // an abandoned generation's
        const auto [first, count] = share(n, r, ranks_.size);
        if (got.value().results.size() != count) continue;
        std::move(got.value().results.begin(), got.value().results.end(),
                  out.begin() + static_cast<long>(first));
        pending[static_cast<size_t>(r)] = 0;
        --left;
        any = true;
      }
      if (!any) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    for (int r = 1; r < ranks_.size; ++r) {
      if (!pending[static_cast<size_t>(r)]) continue;
      const auto [first, count] = share(n, r, ranks_.size);
      for (size_t i = first; i < first + count; ++i) out[i].cancelled = true;
    }
    traffic_->transfer_ms += moving;
    traffic_->waiting_ms += msSince(waiting) - moving;
  }

  Ranks ranks_;
  Traffic* traffic_;
  std::uint64_t id_;
};

// A worker's share evaluated on its threads while this (the MPI) thread watches for a cancel.
wire::Bytes evaluateShare(const search::Problem& problem, const wire::Points& share, int threads) {
  std::atomic<bool> cancel{false};
  std::vector<search::Evaluation> results;
  std::atomic<bool> done{false};
  std::thread work([&] {
    results = search::evaluateAll(problem, share.points, threads, &cancel);
    done = true;
  });
  while (!done) {
    if (!cancel && arrived(0, kCancel)) {
      Result<wire::Points> which = wire::unpackPoints(receive(0, kCancel));
      if (which.ok() && which.value().id == share.id) cancel = true;
    } else if (!cancel && arrived(0, kStop)) {
      cancel = true;  // the stop stays queued for serve()
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  work.join();
  return wire::packResults(share.id, results);
}

}  // namespace

Result<Ranks> start() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
  if (provided < MPI_THREAD_SERIALIZED) {
    MPI_Finalize();
    return Status::error(
        "MPI: this MPI library gives no MPI_THREAD_SERIALIZED support, which the "
        "search's thread needs");
  }
  Ranks ranks;
  MPI_Comm_rank(MPI_COMM_WORLD, &ranks.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks.size);
  return ranks;
}

void finish() {
  MPI_Finalize();
}

void abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
}

Status handshake(const Ranks& ranks, const search::Problem& problem) {
  const std::uint64_t mine = wire::fingerprint(problem);
  for (int r = 1; r < ranks.size; ++r) {
    const wire::Bytes hello = receive(r, kHello);
    Result<wire::Points> got = wire::unpackPoints(hello);
    if (!got.ok() || got.value().id != mine)
      return Status::error("MPI: rank " + std::to_string(r) +
                           " built another problem than rank 0 (other files or flags on that "
                           "machine?): every rank must see the same rig, clip and settings");
  }
  return Status();
}

search::GenerationEvaluator coordinator(const Ranks& ranks, Traffic* traffic) {
  auto next = std::make_shared<std::uint64_t>(0);
  return [ranks, traffic, next](const search::Problem& problem,
                                const std::vector<std::vector<double>>& points, int threads,
                                const std::atomic<bool>* cancel, bool record) {
    Generation generation(ranks, traffic, ++*next);
    return generation.run(problem, points, threads, cancel, record);
  };
}

void stopWorkers(const Ranks& ranks) {
  for (int r = 1; r < ranks.size; ++r) send({}, r, kStop);
}

int serve(const Ranks& ranks, const search::Problem& problem, int threads) {
  // Hello: an empty share whose id is this rank's fingerprint of the problem.
  send(wire::packPoints(wire::fingerprint(problem), {}), 0, kHello);
  for (;;) {
    const MPI_Status status = waitFor(0, MPI_ANY_TAG);
    const wire::Bytes bytes = receive(0, status.MPI_TAG);
    if (status.MPI_TAG == kStop) return 0;
    if (status.MPI_TAG != kPoints) continue;  // a cancel that came after its share was done
    Result<wire::Points> share = wire::unpackPoints(bytes);
    if (!share.ok()) {
      std::fprintf(stderr, "sinew: MPI rank %d: %s\n", ranks.rank, share.message().c_str());
      return 1;
    }
    send(evaluateShare(problem, share.value(), threads), 0, kResults);
  }
}

void dispatch(const Ranks& ranks, int jobs,
              const std::function<void(int job, int rank, int exit_code)>& done) {
  int next = 0, told = 0;
  while (told < ranks.size - 1) {
    const MPI_Status status = waitFor(MPI_ANY_SOURCE, kAsk);
    int report[2] = {-1, 0};  // the job finished and its exit code
    MPI_Recv(report, 2, MPI_INT, status.MPI_SOURCE, kAsk, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (report[0] >= 0) done(report[0], status.MPI_SOURCE, report[1]);
    const int job = next < jobs ? next++ : -1;
    if (job < 0) ++told;
    MPI_Send(&job, 1, MPI_INT, status.MPI_SOURCE, kJob, MPI_COMM_WORLD);
  }
}

int nextJob(int finished, int exit_code) {
  int report[2] = {finished, exit_code};
  MPI_Send(report, 2, MPI_INT, 0, kAsk, MPI_COMM_WORLD);
  (void)waitFor(0, kJob);
  int job = -1;
  MPI_Recv(&job, 1, MPI_INT, 0, kJob, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return job;
}
#endif

}  // namespace sinew::app::distributed
