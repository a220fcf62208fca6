// core/sweep_scheduler.hpp in one process (no mpirun): conditions computed and absorbed in order,
// packed results read back bit for bit, a numerical failure carried through a packed result with
// its message unchanged. The distributed path is tests/cli/test_mpi_sweeps.cpp (mpirun -np 2).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "core/kind_registry.hpp"
#include "core/sweep_scheduler.hpp"

namespace granflow::core {
namespace {

TEST(Packer, ReadsBackWhatWasWrittenBitForBit) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> numbers = {0.1, -0.0, 1e-308, std::numeric_limits<double>::infinity(),
                                       nan};
  const std::string text("with a \0 inside", 15);
  Packer p;
  p.number(1.0 / 3.0).integer(-42).text(text).numbers(numbers).numbers({}).text("");
  const std::string bytes = p.take();
  Unpacker u(bytes);
  EXPECT_EQ(u.number(), 1.0 / 3.0);
  EXPECT_EQ(u.integer(), -42);
  EXPECT_EQ(u.text(), text);
  const auto back = u.numbers();
  ASSERT_EQ(back.size(), numbers.size());
  // Bitwise: -0.0 stays negative, NaN stays NaN (the distributed run must give the serial bytes).
  EXPECT_EQ(std::memcmp(back.data(), numbers.data(), numbers.size() * sizeof(double)), 0);
  EXPECT_TRUE(u.numbers().empty());
  EXPECT_EQ(u.text(), "");
  EXPECT_TRUE(u.done());
  EXPECT_THROW(u.number(), std::runtime_error);  // reading past the end is an error, not garbage
}

TEST(Packer, NumericalFailureComesBackWithTheSameMessage) {
  const NumericalFailure original(17, "REV point", "granular_temperature", -1.5e-9, "negative");
  Packer p;
  p.number(2.5);  // data before the failure, as a kind packs it
  pack_numerical_failure(p, original);
  const std::string bytes = p.take();
  Unpacker u(bytes);
  EXPECT_EQ(u.number(), 2.5);
  try {
    throw_numerical_failure(u);
    FAIL() << "throw_numerical_failure returned";
  } catch (const NumericalFailure& e) {
    EXPECT_STREQ(e.what(), original.what());
    EXPECT_EQ(e.step, 17);
    EXPECT_EQ(e.point, "REV point");
    EXPECT_EQ(e.variable, "granular_temperature");
    EXPECT_EQ(e.value, -1.5e-9);
  }
}

class SerialSweep : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("granflow_sweep_" + std::to_string(::getpid()));
    run_case_.emplace(Case::parse("kind: test\nname: sweep\n", "sweep.yaml", {}, schema_));
    ctx_ = std::make_unique<RunContext>(*run_case_, dir_, true, true);
  }
  void TearDown() override {
    ctx_.reset();
    std::filesystem::remove_all(dir_);
  }
  Schema schema_ = kind_header("test", "", "a kind for tests");
  std::filesystem::path dir_;
  std::optional<Case> run_case_;
  std::unique_ptr<RunContext> ctx_;
};

TEST_F(SerialSweep, ComputeAndAbsorbAlternateInConditionOrder) {
  EXPECT_TRUE(owns_outputs());  // no mpirun: this process writes the run directory
  std::vector<std::string> events;
  const bool owner = run_conditions(
      *ctx_, 4,
      [&](const ConditionContext& c) {
        EXPECT_EQ(c.rank, 0);
        EXPECT_EQ(c.run_directory, dir_);
        EXPECT_EQ(c.log, ctx_->log);  // one process: the run's own logger, lines as they come
        events.push_back("compute " + std::to_string(c.index));
        return Packer().number(c.index * 0.5).take();
      },
      [&](std::size_t n, const std::string& bytes) {
        Unpacker u(bytes);
        EXPECT_EQ(u.number(), n * 0.5);
        events.push_back("absorb " + std::to_string(n));
      });
  EXPECT_TRUE(owner);
  EXPECT_EQ(events, (std::vector<std::string>{"compute 0", "absorb 0", "compute 1", "absorb 1",
                                              "compute 2", "absorb 2", "compute 3", "absorb 3"}));
}

TEST_F(SerialSweep, AFailingConditionStopsTheSweepAsBefore) {
  int absorbed = 0;
  EXPECT_THROW(run_conditions(
                   *ctx_, 3,
                   [&](const ConditionContext& c) -> std::string {
                     if (c.index == 1) throw NumericalFailure(3, "REV point", "T", NAN, "x");
                     return "";
                   },
                   [&](std::size_t, const std::string&) { ++absorbed; }),
               NumericalFailure);
  EXPECT_EQ(absorbed, 1);  // condition 0 only: nothing after the failure runs
}

}  // namespace
}  // namespace granflow::core
