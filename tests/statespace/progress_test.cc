// The progress line (util/progress.h): its percentage never goes backwards when a new estimate
// of the total grows (issue 42: "2288/~2574 (89%)" then "2404/~2808 (86%)"), stays below 100 %
// until the work is done, and follows the work up again once it catches up.
#include "util/progress.h"

#include <gtest/gtest.h>

#include <regex>
#include <string>

namespace hapstate {
namespace {

int percent_of(const std::string& line) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(line, m, std::regex("\\((\\d+)%\\)"))) << line;
  return std::stoi(m[1]);
}

TEST(Progress, PercentageNeverGoesBackwards) {
  Progress p("work", 2574, nullptr);
  p.set_total(2574, true);
  p.update(2288);
  EXPECT_EQ(percent_of(p.line()), 89);
  p.set_total(2808, true);  // the estimate grew: 2404 / 2808 would be 86 %
  p.update(2404);
  EXPECT_EQ(percent_of(p.line()), 89);
  EXPECT_NE(p.line().find("2404/~2808"), std::string::npos) << p.line();
  p.update(2600);  // caught up: 93 %
  EXPECT_EQ(percent_of(p.line()), 93);
  p.set_total(100000, true);  // a huge re-estimate still holds it
  EXPECT_EQ(percent_of(p.line()), 93);
  p.set_total(2601, true);  // almost done: never 100 % before the end
  EXPECT_EQ(percent_of(p.line()), 99);
  p.set_total(2600, false);
  EXPECT_EQ(percent_of(p.line(/*final=*/true)), 100);
  int last = 0;
  Progress q("grow", 10, nullptr);
  for (int done = 0; done <= 1000; done += 7) {
    q.set_total(10 + 2 * done, true);  // the total keeps growing ahead of the work
    q.update(done);
    const int shown = percent_of(q.line());
    EXPECT_GE(shown, last) << done;
    last = shown;
  }
}

TEST(Progress, AModelsEtaReplacesTheRatesUntilWithdrawn) {
  Progress p("work", 1000, nullptr);
  p.set_total(1000, true);
  p.update(500);
  p.set_eta(3725);  // a model's estimate: 1 h 02 min
  EXPECT_NE(p.line().find("ETA ~1h02m"), std::string::npos) << p.line();
  p.set_eta(42.0);
  EXPECT_NE(p.line().find("ETA ~4"), std::string::npos) << p.line();  // 42 s, counting down
  p.set_eta(-1);  // withdrawn: the rate's ETA again (500 done over a few microseconds: ~0 s)
  EXPECT_EQ(p.line().find("ETA ~4"), std::string::npos) << p.line();
}

TEST(Progress, DurationsReadable) {
  EXPECT_EQ(format_duration(12.34), "12.3s");
  EXPECT_EQ(format_duration(185), "3m05s");
  EXPECT_EQ(format_duration(3725), "1h02m");
  EXPECT_EQ(format_duration(-1), "?");
  EXPECT_EQ(format_duration(1e300), ">1000h");  // never an int overflow
}

}  // namespace
}  // namespace hapstate
