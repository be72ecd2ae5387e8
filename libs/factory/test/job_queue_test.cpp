// JobQueue: which queued job comes into work when only some are ready.
#include "sf/factory/job_queue.hpp"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace sf::factory {
namespace {

using namespace std::chrono_literals;

Operation load_into(double box) {
  return Operation{std::string(kLoad), {{"box", box}}};
}

// Ready: the operation's box is one of `here`.
auto boxes_at_station(std::set<double> here) {
  return [here = std::move(here)](const Operation& op) { return here.contains(*op.param("box")); };
}

class JobQueueTest : public ::testing::Test {
 protected:
  JobQueueTest() {
    for (int box = 1; box <= 3; ++box) {
      EXPECT_TRUE(jobs_.add("job" + std::to_string(box), load_into(box), 1s));
    }
  }
  JobQueue jobs_;
};

TEST_F(JobQueueTest, TheFirstReadyJobBeginsAndTheOthersKeepTheirOrder) {
  ASSERT_TRUE(jobs_.begin_next(boxes_at_station({2, 3})));
  EXPECT_EQ(jobs_.current()->id, "job2");  // FIFO among the ready ones
  EXPECT_EQ(jobs_.queued(), 2U);
  jobs_.finish(true, "done");
  // The queue keeps job1 before job3: with both ready, job1 goes first.
  ASSERT_TRUE(jobs_.begin_next(boxes_at_station({1, 3})));
  EXPECT_EQ(jobs_.current()->id, "job1");
  jobs_.finish(true, "done");
  ASSERT_TRUE(jobs_.begin_next(boxes_at_station({3})));
  EXPECT_EQ(jobs_.current()->id, "job3");
}

TEST_F(JobQueueTest, NothingBeginsWhenNoJobIsReady) {
  EXPECT_FALSE(jobs_.begin_next(boxes_at_station({})));
  EXPECT_EQ(jobs_.current(), nullptr);
  EXPECT_EQ(jobs_.queued(), 3U);
  EXPECT_EQ(jobs_.backlog(), 3s);
}

TEST_F(JobQueueTest, NothingBeginsWhileAJobIsInWork) {
  ASSERT_TRUE(jobs_.begin_next());
  EXPECT_EQ(jobs_.current()->id, "job1");  // without a predicate: plain FIFO
  EXPECT_FALSE(jobs_.begin_next(boxes_at_station({2})));
  EXPECT_EQ(jobs_.current()->id, "job1");
}

TEST_F(JobQueueTest, AJobsActiveTimeCountsOnlyFromItsBegin) {
  ASSERT_TRUE(jobs_.begin_next(boxes_at_station({3})));
  EXPECT_EQ(jobs_.current()->active, 0ns);
  jobs_.current()->active += 500ms;
  jobs_.finish(true, "done");
  ASSERT_TRUE(jobs_.begin_next());
  EXPECT_EQ(jobs_.current()->id, "job1");
  EXPECT_EQ(jobs_.current()->active, 0ns);
}

TEST_F(JobQueueTest, TheWorkingTimeSumsTheActiveTimeOfEveryJobInWork) {
  const PackMLUnit unit(SteadyClock::instance());
  EXPECT_EQ(jobs_.status(unit).working_time, 0ns);
  ASSERT_TRUE(jobs_.begin_next());
  jobs_.current()->active += 700ms;
  EXPECT_EQ(jobs_.status(unit).working_time, 700ms);  // the job in work counts as it goes
  jobs_.finish(true, "done");
  ASSERT_TRUE(jobs_.begin_next());
  jobs_.current()->active += 300ms;
  jobs_.finish(false, "cancelled");   // a job that failed was worked on too
  EXPECT_TRUE(jobs_.cancel("job3"));  // never in work: no time
  EXPECT_EQ(jobs_.status(unit).working_time, 1s);
}

}  // namespace
}  // namespace sf::factory
