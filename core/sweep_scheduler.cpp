#include "core/sweep_scheduler.hpp"

#include <fmt/format.h>
#include <spdlog/sinks/base_sink.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <future>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>

#include "core/interrupt.hpp"

#if GRANFLOW_HAVE_MPI
// The C API only (linked as MPI::MPI_C): no deprecated C++ bindings.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace granflow::core {

// ---- Packer / Unpacker -----------------------------------------------------------------------

Packer& Packer::number(double value) {
  bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  return *this;
}

Packer& Packer::integer(std::int64_t value) {
  bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  return *this;
}

Packer& Packer::text(std::string_view value) {
  integer(static_cast<std::int64_t>(value.size()));
  bytes_.append(value);
  return *this;
}

Packer& Packer::numbers(const std::vector<double>& values) {
  integer(static_cast<std::int64_t>(values.size()));
  bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
  return *this;
}

void Unpacker::read(void* destination, std::size_t size) {
  if (position_ + size > bytes_.size())
    throw std::runtime_error("a condition's packed result is shorter than what is read from it");
  std::memcpy(destination, bytes_.data() + position_, size);
  position_ += size;
}

double Unpacker::number() {
  double value;
  read(&value, sizeof value);
  return value;
}

std::int64_t Unpacker::integer() {
  std::int64_t value;
  read(&value, sizeof value);
  return value;
}

std::string Unpacker::text() {
  std::string value(static_cast<std::size_t>(integer()), '\0');
  read(value.data(), value.size());
  return value;
}

std::vector<double> Unpacker::numbers() {
  std::vector<double> values(static_cast<std::size_t>(integer()));
  read(values.data(), values.size() * sizeof(double));
  return values;
}

void pack_numerical_failure(Packer& packer, const NumericalFailure& failure) {
  packer.integer(failure.step).text(failure.point).text(failure.variable).number(failure.value);
  packer.text(failure.why);
}

void throw_numerical_failure(Unpacker& unpacker) {
  const std::int64_t step = unpacker.integer();
  const std::string point = unpacker.text(), variable = unpacker.text();
  const double value = unpacker.number();
  throw NumericalFailure(step, point, variable, value, unpacker.text());
}

// ---- one condition computed away from the run's logger ---------------------------------------

namespace {

// Collects a condition's log lines (level, text) to be written to log.txt by rank 0.
class CaptureSink : public spdlog::sinks::base_sink<std::mutex> {
 public:
  std::vector<std::pair<int, std::string>> lines;

 protected:
  void sink_it_(const spdlog::details::log_msg& message) override {
    lines.emplace_back(static_cast<int>(message.level),
                       std::string(message.payload.begin(), message.payload.end()));
  }
  void flush_() override {}
};

enum Failure : int { none = 0, numerical = 1, bad_input = 2, other = 3 };

// A computed condition as it travels back to rank 0.
struct Outcome {
  std::size_t index = 0;
  int rank = 0;
  double seconds = 0;
  int failure = none;
  std::string what;  // exception message (a numerical failure: its `why`)
  std::int64_t step = 0;
  std::string point, variable;
  double value = 0;
  std::vector<std::pair<int, std::string>> lines;
  std::string payload;

  std::string pack() const {
    Packer p;
    p.integer(static_cast<std::int64_t>(index)).integer(rank).number(seconds).integer(failure);
    p.text(what).integer(step).text(point).text(variable).number(value);
    p.integer(static_cast<std::int64_t>(lines.size()));
    for (const auto& [level, line] : lines) p.integer(level).text(line);
    p.text(payload);
    return p.take();
  }
  static Outcome unpack(std::string_view bytes) {
    Unpacker u(bytes);
    Outcome o;
    o.index = static_cast<std::size_t>(u.integer());
    o.rank = static_cast<int>(u.integer());
    o.seconds = u.number();
    o.failure = static_cast<int>(u.integer());
    o.what = u.text();
    o.step = u.integer();
    o.point = u.text();
    o.variable = u.text();
    o.value = u.number();
    const auto count = u.integer();
    for (std::int64_t i = 0; i < count; ++i) {
      const int level = static_cast<int>(u.integer());
      o.lines.emplace_back(level, u.text());
    }
    o.payload = u.text();
    return o;
  }
};

Outcome compute_outcome(const ComputeCondition& compute, std::size_t index,
                        const std::filesystem::path& run_directory, int rank) {
  auto sink = std::make_shared<CaptureSink>();
  auto log = std::make_shared<spdlog::logger>("granflow", sink);
  log->set_level(spdlog::level::info);  // the level of log.txt (core/run.cpp)
  Outcome o;
  o.index = index;
  o.rank = rank;
  const auto start = std::chrono::steady_clock::now();
  try {
    o.payload = compute({index, log, run_directory, rank});
  } catch (const NumericalFailure& e) {
    o.failure = numerical;
    o.what = e.why;  // rebuilt on rank 0 with the step, point and variable
    o.step = e.step;
    o.point = e.point;
    o.variable = e.variable;
    o.value = e.value;
  } catch (const CaseError& e) {
    o.failure = bad_input;
    o.what = e.what();
  } catch (const std::exception& e) {
    o.failure = other;
    o.what = e.what();
  } catch (...) {
    o.failure = other;
    o.what = "unknown exception";
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  o.lines = std::move(sink->lines);
  return o;
}

// Rank 0: the condition's log lines, then its failure rethrown as the serial run would have
// thrown it, else its result absorbed.
void absorb_outcome(RunContext& ctx, const Outcome& o, const AbsorbCondition& absorb) {
  for (const auto& [level, line] : o.lines)
    ctx.log->log(static_cast<spdlog::level::level_enum>(level), "{}", line);
  switch (o.failure) {
    case numerical:
      throw NumericalFailure(o.step, o.point, o.variable, o.value, o.what);
    case bad_input:
      throw CaseError(o.what);
    case other:
      throw std::runtime_error(o.what);
    default:
      absorb(o.index, o.payload);
  }
}

}  // namespace

// ---- MPI ---------------------------------------------------------------------------------------

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK"})
    if (const char* value = std::getenv(name); value && *value) return true;
  return false;
}

#if GRANFLOW_HAVE_MPI

namespace {

// Messages of the queue. Rank r > 0 -> 0: ready (empty), result (an Outcome), leaving (empty).
// Rank 0 -> r: work (condition index + run directory), end (empty: no more work in this sweep).
enum Tag : int { tag_ready = 1, tag_result = 2, tag_leaving = 3, tag_work = 4, tag_end = 5 };

// Open MPI's blocking calls busy-poll a core; a rank waiting for a long DEM point must not take
// a core from the one running it, so waits poll with a short sleep instead.
constexpr auto poll_interval = std::chrono::milliseconds(2);

bool mpi_active() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) return false;
  MPI_Finalized(&finalised);
  return !finalised;
}

int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int world_size() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

bool probe(int source, MPI_Status& status) {
  int flag = 0;
  MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
  return flag != 0;
}

MPI_Status wait_message(int source) {
  MPI_Status status;
  while (!probe(source, status)) std::this_thread::sleep_for(poll_interval);
  return status;
}

std::string receive(const MPI_Status& probed) {
  int count = 0;
  MPI_Get_count(&probed, MPI_BYTE, &count);
  std::string bytes(static_cast<std::size_t>(count), '\0');
  MPI_Recv(bytes.data(), count, MPI_BYTE, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return bytes;
}

void send(const std::string& bytes, int destination, int tag) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag,
           MPI_COMM_WORLD);
}

// Rank > 0: ask for conditions until rank 0 says end.
void serve_conditions(const ComputeCondition& compute, int rank) {
  send("", 0, tag_ready);
  while (true) {
    const MPI_Status status = wait_message(0);
    const std::string bytes = receive(status);
    if (status.MPI_TAG == tag_end) return;
    Unpacker work(bytes);
    const auto index = static_cast<std::size_t>(work.integer());
    const std::filesystem::path run_directory = work.text();
    send(compute_outcome(compute, index, run_directory, rank).pack(), 0, tag_result);
  }
}

// Rank 0: the queue, its own share of the conditions on a thread, absorption in order.
void lead_conditions(RunContext& ctx, std::size_t count, const ComputeCondition& compute,
                     const AbsorbCondition& absorb, int size) {
  auto& log = *ctx.log;
  const std::filesystem::path run_directory = ctx.directory.path();
  std::size_t next = 0, absorbed = 0;
  std::map<std::size_t, Outcome> done;
  std::future<Outcome> local;
  bool local_busy = false;
  std::vector<char> released_rank(static_cast<std::size_t>(size), 0);
  int released = 0;  // other ranks sent `end` (or gone) in this sweep
  std::exception_ptr failure;
  log.info("{} conditions on {} MPI ranks (rank 0 computes too; dynamic queue)", count, size);

  auto finished = [&](const Outcome& o) {
    if (o.failure == none)
      log.info("condition {}: finished on rank {} in {:.3f} s", o.index, o.rank, o.seconds);
    else
      log.info("condition {}: failed on rank {} after {:.3f} s", o.index, o.rank, o.seconds);
  };
  while (true) {
    bool active = false;
    // An interrupted run (SIGINT/SIGTERM) hands out nothing more and absorbs what was started.
    const bool stopping = failure || interrupted();
    if (!stopping && !local_busy && next < count) {
      log.info("condition {}: started on rank 0", next);
      local = std::async(std::launch::async, compute_outcome, std::cref(compute), next++,
                         run_directory, 0);
      local_busy = active = true;
    }
    // One rank at a time, and only ranks still in this sweep: a rank released here goes on to
    // say `leaving` (MpiRanks::leave_run), a message for the end of the run, not for this loop.
    for (int from = 1; from < size; ++from) {
      MPI_Status status;
      if (released_rank[from] || !probe(from, status)) continue;
      active = true;
      if (status.MPI_TAG == tag_leaving) {  // gone without asking (it stopped before the sweep):
        released_rank[from] = 1;            // leave_run receives the message
        ++released;
        continue;
      }
      const std::string bytes = receive(status);
      if (status.MPI_TAG == tag_result) {
        Outcome o = Outcome::unpack(bytes);
        finished(o);
        done.emplace(o.index, std::move(o));
      }
      // A result also says the rank is free again.
      if (!stopping && next < count) {
        log.info("condition {}: started on rank {}", next, from);
        send(
            Packer().integer(static_cast<std::int64_t>(next++)).text(run_directory.string()).take(),
            from, tag_work);
      } else {
        send("", from, tag_end);
        released_rank[from] = 1;
        ++released;
      }
    }
    if (local_busy && local.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      Outcome o = local.get();
      finished(o);
      done.emplace(o.index, std::move(o));
      local_busy = false;
      active = true;
    }
    while (!failure && done.count(absorbed)) {
      try {
        absorb_outcome(ctx, done.at(absorbed), absorb);
      } catch (...) {
        // Stop handing out conditions; the ranks still busy finish theirs and are released.
        failure = std::current_exception();
      }
      done.erase(absorbed++);
      active = true;
    }
    if (released == size - 1 && !local_busy &&
        (failure || absorbed == count || (stopping && absorbed == next)))
      break;
    if (!active) std::this_thread::sleep_for(poll_interval);
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace

bool owns_outputs() { return !mpi_active() || world_rank() == 0; }

bool run_conditions(RunContext& ctx, std::size_t count, const ComputeCondition& compute,
                    const AbsorbCondition& absorb) {
  if (mpi_active() && world_size() > 1) {
    const int rank = world_rank();
    if (rank != 0) {
      serve_conditions(compute, rank);
      return false;
    }
    lead_conditions(ctx, count, compute, absorb, world_size());
    return true;
  }
  for (std::size_t n = 0; n < count && !interrupted(); ++n)
    absorb(n, compute({n, ctx.log, ctx.directory.path(), 0}));
  return true;
}

MpiRanks::MpiRanks(int& argc, char**& argv) {
  if (!launched_by_mpirun()) return;
  int provided = 0;
  // Rank 0 computes on a second thread that makes no MPI call: FUNNELED is enough.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  initialised_ = true;
  rank_ = world_rank();
  size_ = world_size();
}

MpiRanks::~MpiRanks() {
  if (initialised_) MPI_Finalize();
}

void MpiRanks::leave_run() {
  if (!initialised_ || size_ == 1) return;
  if (rank_ != 0) {
    send("", 0, tag_leaving);
    return;
  }
  int remaining = size_ - 1;
  while (remaining > 0) {
    const MPI_Status status = wait_message(MPI_ANY_SOURCE);
    receive(status);
    if (status.MPI_TAG == tag_leaving)
      --remaining;
    else if (status.MPI_TAG == tag_ready)
      send("", status.MPI_SOURCE, tag_end);  // it waits for a sweep that will not come
  }
}

#else  // built without MPI: always one process

bool owns_outputs() { return true; }

bool run_conditions(RunContext& ctx, std::size_t count, const ComputeCondition& compute,
                    const AbsorbCondition& absorb) {
  for (std::size_t n = 0; n < count && !interrupted(); ++n)
    absorb(n, compute({n, ctx.log, ctx.directory.path(), 0}));
  return true;
}

MpiRanks::MpiRanks(int&, char**&) {
  if (launched_by_mpirun())
    throw std::runtime_error(
        "started by mpirun, but this granflow was built without MPI (find_package(MPI) failed): "
        "it cannot distribute a sweep; run it without mpirun");
}

MpiRanks::~MpiRanks() = default;

void MpiRanks::leave_run() {}

#endif

}  // namespace granflow::core
