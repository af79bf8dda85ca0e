// dlo::runApp: the exit statuses the README promises (1 bad input or output, 2 command-line
// mistake) and the one line on stderr.
#include "dlo/app/app_main.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace dlo {
namespace {

/// The status runApp returns for `body` and what it printed on stderr.
template <typename Body>
std::pair<int, std::string> run(Body body) {
  testing::internal::CaptureStderr();
  const int status = runApp("prog", body);
  return {status, testing::internal::GetCapturedStderr()};
}

TEST(RunApp, ReturnsTheBodysOwnStatus) {
  EXPECT_EQ(run([] { return 3; }).first, 3);
  EXPECT_EQ(run([] { return 0; }).first, 0);
}

TEST(RunApp, AUsageErrorExitsTwoWithItsMessage) {
  const auto [status, err] = run([]() -> int { throw UsageError("unknown option '--x'."); });
  EXPECT_EQ(status, 2);
  EXPECT_EQ(err, "prog: unknown option '--x'.\n");
}

TEST(RunApp, InputAndOutputErrorsExitOneWithTheirMessage) {
  auto [status, err] = run([]() -> int { throw InputError("cannot open 'a.bin'."); });
  EXPECT_EQ(status, 1);
  EXPECT_EQ(err, "prog: cannot open 'a.bin'.\n");
  std::tie(status, err) = run([]() -> int { throw OutputError("cannot write 'b.tum' (x)."); });
  EXPECT_EQ(status, 1);
  EXPECT_EQ(err, "prog: cannot write 'b.tum' (x).\n");
}

TEST(RunApp, AnyOtherExceptionExitsOneWithItsFirstLine) {
  const auto [status, err] =
      run([]() -> int { throw std::runtime_error("first line\ncall stack"); });
  EXPECT_EQ(status, 1);
  EXPECT_EQ(err, "prog: unexpected error: first line\n");
}

}  // namespace
}  // namespace dlo
