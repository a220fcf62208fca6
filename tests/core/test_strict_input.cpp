// Strict input: a key given twice in one mapping is an error naming both lines (yaml-cpp alone
// keeps one silently), integer keys are read exactly within their range (1e20 used to wrap to
// INT64_MIN), and a case or included file that is not a regular file (FIFO, directory) is
// refused at once instead of blocking.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <limits>
#include <thread>

#include "core/case.hpp"
#include "core/kind_registry.hpp"

using granflow::core::Case;
using granflow::core::CaseError;
using granflow::core::Field;
using granflow::core::Schema;
namespace fs = std::filesystem;

namespace {

Schema strict_schema() {
  Schema s = granflow::core::kind_header("rev", "simple_shear", "test schema");
  auto& m = s.section("material", "grains");
  m.number("diameter", "m", "grain diameter").required().greater_than(0);
  m.number("restitution", "", "restitution").required().greater_than(0).at_most(1);
  auto& l = s.section("loading", "loading");
  l.number("shear_rate", "1/s", "shear rate").required().greater_than(0).sweepable();
  l.integer("steps", "steps").default_value("10").greater_than(0).sweepable();
  l.integer("offset", "an integer without stated bounds").default_value("0");
  l.integer("big", "an integer with a stated bound beyond int")
      .default_value("1")
      .at_least(0)
      .at_most(9.3e18);
  return s;
}

const Schema& schema() {
  static const Schema s = strict_schema();
  return s;
}

const std::string good =
    "kind: rev\n"           // 1
    "test: simple_shear\n"  // 2
    "material:\n"           // 3
    "  diameter: 1.0e-3\n"  // 4
    "  restitution: 0.7\n"  // 5
    "loading:\n"            // 6
    "  shear_rate: 10\n";   // 7

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    Case::parse(text, "case.yaml", sets, schema());
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

std::string load_error(const fs::path& file, const std::vector<std::string>& sets = {}) {
  try {
    Case::load(file, sets, schema());
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

fs::path scratch_dir(const std::string& name) {
  const auto dir =
      fs::temp_directory_path() / ("granflow_strict_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Runs `f` (which loads from `fifo`) on a thread; if it has not returned within 10 s it is
// blocked on the FIFO: the test fails and a writer is opened to release it.
std::string error_within_timeout(const fs::path& fifo, std::function<std::string()> f) {
  std::packaged_task<std::string()> task(std::move(f));
  auto result = task.get_future();
  std::thread worker(std::move(task));
  if (result.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    ADD_FAILURE() << "loading blocked on the FIFO " << fifo;
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
  }
  worker.join();
  return result.get();
}

}  // namespace

// --- duplicate keys ---------------------------------------------------------------------------

TEST(StrictInput, DuplicateKeyInASectionNamesBothLines) {
  const auto e = error_of(good + "  shear_rate: 50\n");  // line 8, first at line 7
  EXPECT_EQ(e,
            "case.yaml:8: loading.shear_rate: given twice (first at line 7); expected each key "
            "once");
  const auto r = error_of(
      "kind: rev\ntest: simple_shear\nmaterial:\n  restitution: 0.7\n  diameter: 1.0e-3\n"
      "  restitution: 0.2\nloading:\n  shear_rate: 10\n");
  EXPECT_EQ(r,
            "case.yaml:6: material.restitution: given twice (first at line 4); expected each key "
            "once");
}

TEST(StrictInput, DuplicateTopLevelKeyAndSection) {
  EXPECT_EQ(error_of("kind: rev\n" + good),
            "case.yaml:2: kind: given twice (first at line 1); expected each key once");
  // a second material: section would silently replace the whole first one
  const auto e = error_of(good + "material:\n  diameter: 5.0e-3\n  restitution: 0.9\n");
  EXPECT_EQ(e, "case.yaml:8: material: given twice (first at line 3); expected each key once");
}

TEST(StrictInput, DuplicateKeysAtAnyDepthAndInFlowStyle) {
  // found before validation, so at any depth (here inside an unknown nested map) ...
  EXPECT_EQ(error_of(good + "  extra:\n    deeper:\n      a: 1\n      a: 2\n"),
            "case.yaml:11: loading.extra.deeper.a: given twice (first at line 10); expected each "
            "key once");
  // ... in flow mappings and in maps inside lists, and a quoted key is the same key
  EXPECT_NE(error_of(good + "  other: {x: 1, x: 2}\n").find("loading.other.x: given twice"),
            std::string::npos);
  EXPECT_NE(error_of(good + "  list:\n    - {a: 1, b: 2}\n    - {a: 1, a: 2}\n")
                .find("case.yaml:10: loading.list[1].a: given twice (first at line 10)"),
            std::string::npos);
  EXPECT_EQ(error_of(good + "  \"shear_rate\": 50\n"),
            "case.yaml:8: loading.shear_rate: given twice (first at line 7); expected each key "
            "once");
  // the same key in different mappings is fine
  EXPECT_EQ(error_of(good + "  other:\n    shear_rate: 1\n").find("given twice"),
            std::string::npos);
}

TEST(StrictInput, DuplicateSweepKeyAndSetValue) {
  EXPECT_EQ(
      error_of(good + "sweep:\n  loading.shear_rate: [1, 2]\n  loading.shear_rate: [3]\n"),
      "case.yaml:10: sweep.loading.shear_rate: given twice (first at line 9); expected each key "
      "once");
  EXPECT_EQ(error_of(good, {"loading={shear_rate: 1, shear_rate: 2}"}),
            "--set loading={shear_rate: 1, shear_rate: 2}: loading.shear_rate: given twice; "
            "expected each key once");
}

TEST(StrictInput, DuplicateKeyInAnIncludedFileIsLocatedThere) {
  const auto dir = scratch_dir("dup_include");
  std::ofstream(dir / "case.yaml") << "kind: rev\ntest: simple_shear\ninclude: par.yaml\n"
                                      "loading:\n  shear_rate: 10\n";
  std::ofstream(dir / "par.yaml") << "material:\n  diameter: 1.0e-3\n  restitution: 0.7\n"
                                     "  diameter: 2.0e-3\n";
  EXPECT_EQ(load_error(dir / "case.yaml"),
            (dir / "par.yaml").string() +
                ":4: material.diameter: given twice (first at line 2); expected each key once");
  // a duplicate section in the included file
  std::ofstream(dir / "par.yaml") << "material:\n  diameter: 1.0e-3\n  restitution: 0.7\n"
                                     "material:\n  diameter: 1.0e-3\n";
  EXPECT_EQ(load_error(dir / "case.yaml"),
            (dir / "par.yaml").string() +
                ":4: material: given twice (first at line 1); expected each key once");
  // a duplicate in the case file itself, through load()
  std::ofstream(dir / "par.yaml") << "material:\n  diameter: 1.0e-3\n  restitution: 0.7\n";
  std::ofstream(dir / "case.yaml") << "kind: rev\ntest: simple_shear\ninclude: par.yaml\n"
                                      "loading:\n  shear_rate: 10\n  shear_rate: 20\n";
  EXPECT_EQ(load_error(dir / "case.yaml"),
            (dir / "case.yaml").string() +
                ":6: loading.shear_rate: given twice (first at line 5); expected each key once");
  fs::remove_all(dir);
}

// --- integers -----------------------------------------------------------------------------------

TEST(StrictInput, HugeOrFractionalIntegersAreRefusedInTheFile) {
  EXPECT_EQ(error_of(good + "  steps: 1e20\n"),
            "case.yaml:8: loading.steps: value 1e20 is out of range; expected integer > 0 (at "
            "most 2147483647)");
  EXPECT_NE(error_of(good + "  steps: 1e19\n")
                .find("case.yaml:8: loading.steps: value 1e19 is "
                      "out of range"),
            std::string::npos);
  EXPECT_EQ(error_of(good + "  steps: 2.5\n"),
            "case.yaml:8: loading.steps: not an integer; expected integer > 0");
  EXPECT_NE(error_of(good + "  steps: 3.5\n").find("not an integer"), std::string::npos);
  EXPECT_NE(error_of(good + "  steps: abc\n").find("case.yaml:8: loading.steps: not an integer"),
            std::string::npos);
  EXPECT_NE(error_of(good + "  steps: 0x10\n").find("not an integer"), std::string::npos);
  EXPECT_NE(error_of(good + "  steps: .inf\n").find("not an integer"), std::string::npos);
  EXPECT_NE(error_of(good + "  steps: [1]\n").find("not an integer"), std::string::npos);
  // beyond int (the default upper bound) and beyond int64, written as digits
  EXPECT_NE(error_of(good + "  steps: 2147483648\n").find("value 2147483648 is out of range"),
            std::string::npos);
  EXPECT_NE(error_of(good + "  steps: 99999999999999999999\n").find("is out of range"),
            std::string::npos);
  EXPECT_NE(error_of(good + "  offset: -2147483649\n")
                .find("loading.offset: value -2147483649 is "
                      "out of range; expected integer (in "
                      "[-2147483648, 2147483647])"),
            std::string::npos);
}

TEST(StrictInput, HugeOrFractionalIntegersAreRefusedViaSetAndSweep) {
  EXPECT_EQ(error_of(good, {"loading.steps=1e20"}),
            "--set loading.steps=1e20: loading.steps: value 1e20 is out of range; expected "
            "integer > 0 (at most 2147483647)");
  EXPECT_NE(error_of(good, {"loading.steps=1e19"})
                .find("--set loading.steps=1e19: loading.steps: "
                      "value 1e19 is out of range"),
            std::string::npos);
  EXPECT_EQ(error_of(good, {"loading.steps=2.5"}),
            "--set loading.steps=2.5: loading.steps: not an integer; expected integer > 0");
  EXPECT_NE(error_of(good, {"loading.steps=abc"}).find("not an integer"), std::string::npos);
  EXPECT_NE(error_of(good, {"loading.steps=9.3e18"}).find("out of range"), std::string::npos);
  EXPECT_EQ(error_of(good + "sweep:\n  loading.steps: [5, 1e20]\n"),
            "case.yaml:9: sweep.loading.steps[1]: expected integer > 0 (at most 2147483647)");
  EXPECT_NE(error_of(good, {"sweep.loading.steps=[2.5]"})
                .find("sweep.loading.steps[0]: expected "
                      "integer > 0"),
            std::string::npos);
}

TEST(StrictInput, WholeNumbersWithinRangeAreAcceptedExactly) {
  const auto steps = [](const std::string& v) {
    return Case::parse(good, "case.yaml", {"loading.steps=" + v}, schema())
        .integer("loading.steps");
  };
  EXPECT_EQ(steps("7"), 7);
  EXPECT_EQ(steps("+7"), 7);
  EXPECT_EQ(steps("1e6"), 1000000);
  EXPECT_EQ(steps("2.0"), 2);
  EXPECT_EQ(steps("\"12\""), 12);  // quoted, as for numbers
  EXPECT_EQ(steps("2147483647"), 2147483647);
  // a stated bound beyond int is honoured up to int64, digit for digit
  const auto big = [](const std::string& v) {
    return Case::parse(good, "case.yaml", {"loading.big=" + v}, schema()).integer("loading.big");
  };
  EXPECT_EQ(big("9223372036854775807"), std::numeric_limits<long long>::max());
  EXPECT_EQ(big("123456789012345678"), 123456789012345678LL);
  EXPECT_NE(error_of(good, {"loading.big=9223372036854775808"}).find("out of range"),
            std::string::npos);
  EXPECT_NE(error_of(good, {"loading.big=1e19"}).find("out of range"), std::string::npos);
  // a float-notation value beyond 2^53 may not be exact: refused, digits are taken
  EXPECT_NE(error_of(good, {"loading.big=1e17"})
                .find("loading.big: value 1e17 in floating-point "
                      "notation is beyond 2^53"),
            std::string::npos);
  EXPECT_EQ(big("1e15"), 1000000000000000LL);
  // the sweep keeps whole numbers as integers
  const Case c =
      Case::parse(good + "sweep:\n  loading.steps: [5, 1e3]\n", "case.yaml", {}, schema());
  EXPECT_EQ(c.expand_sweep()[1].integer("loading.steps"), 1000);
}

TEST(StrictInput, IntegerFieldBoundsAreExact) {
  Field f("n", granflow::core::ValueType::integer, "", "n");
  EXPECT_EQ(f.integer_min(), std::numeric_limits<int>::min());
  EXPECT_EQ(f.integer_max(), std::numeric_limits<int>::max());
  f.greater_than(0).less_than(10.5);
  EXPECT_EQ(f.integer_min(), 1);
  EXPECT_EQ(f.integer_max(), 10);
  long long v = 0;
  EXPECT_EQ(f.parse_integer("10", v), Field::IntegerStatus::ok);
  EXPECT_EQ(v, 10);
  EXPECT_EQ(f.parse_integer("11", v), Field::IntegerStatus::out_of_range);
  EXPECT_EQ(f.parse_integer("0", v), Field::IntegerStatus::out_of_range);
  EXPECT_EQ(f.parse_integer("", v), Field::IntegerStatus::not_integer);
  EXPECT_EQ(f.parse_integer("-", v), Field::IntegerStatus::not_integer);
  EXPECT_EQ(f.parse_integer("++1", v), Field::IntegerStatus::not_integer);
  EXPECT_EQ(f.parse_integer("1 ", v), Field::IntegerStatus::not_integer);
  EXPECT_EQ(f.parse_integer("nan", v), Field::IntegerStatus::not_integer);
  EXPECT_EQ(f.parse_integer("1e400", v), Field::IntegerStatus::out_of_range);
}

// --- not a regular file -------------------------------------------------------------------------

TEST(StrictInput, AFifoAsCaseFileIsRefusedWithoutBlocking) {
  const auto dir = scratch_dir("fifo_case");
  const auto fifo = dir / "case.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(error_within_timeout(fifo, [&] { return load_error(fifo); }),
            fifo.string() + ": not a regular file");
  EXPECT_EQ(error_within_timeout(fifo,
                                 [&]() -> std::string {
                                   try {
                                     granflow::core::peek_kind(fifo);
                                   } catch (const CaseError& e) {
                                     return e.what();
                                   }
                                   return "";
                                 }),
            fifo.string() + ": not a regular file");
  fs::remove_all(dir);
}

TEST(StrictInput, AFifoOrDirectoryAsIncludeIsRefusedWithoutBlocking) {
  const auto dir = scratch_dir("fifo_include");
  const auto fifo = dir / "par.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::ofstream(dir / "case.yaml") << good << "include: par.yaml\n";  // line 8
  EXPECT_EQ(
      error_within_timeout(fifo, [&] { return load_error(dir / "case.yaml"); }),
      fifo.string() + ": not a regular file (included at " + (dir / "case.yaml").string() + ":8)");
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "case.yaml") << good << "include: sub\n";
  EXPECT_EQ(load_error(dir / "case.yaml"), (dir / "sub").string() +
                                               ": not a regular file (included at " +
                                               (dir / "case.yaml").string() + ":8)");
  EXPECT_EQ(load_error(dir / "sub"), (dir / "sub").string() + ": not a regular file");
  EXPECT_EQ(load_error(dir / "missing.yaml"),
            (dir / "missing.yaml").string() + ": cannot open the case file");
  fs::remove_all(dir);
}
