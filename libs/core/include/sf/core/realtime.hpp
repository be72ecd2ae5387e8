// Real-time scheduling for cyclic threads (an EtherCAT cycle, a controller's
// loop): SCHED_FIFO and locked memory keep page faults and other processes
// out of the cycle. Without CAP_SYS_NICE / CAP_IPC_LOCK the thread stays a
// normal one; callers report which they got.
#pragma once

#include <thread>

namespace sf {

// Locks the process's memory and gives `thread` SCHED_FIFO at `priority`;
// false when the process may not.
bool try_realtime(std::thread& thread, int priority);

}  // namespace sf
