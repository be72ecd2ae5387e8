#include "sf/core/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

namespace sf {

bool try_realtime(std::thread& thread, int priority) {
  (void)mlockall(MCL_CURRENT | MCL_FUTURE);
  sched_param param{};
  param.sched_priority = priority;
  return pthread_setschedparam(thread.native_handle(), SCHED_FIFO, &param) == 0;
}

}  // namespace sf
