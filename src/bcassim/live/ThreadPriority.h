// Threads working behind the camera (the filter in the asynchronous mode, the real-time model's
// tangent builds) give way to the real-time side: on two cores three threads compete, and the
// answer to the frame is what must not wait.
#pragma once

namespace bcassim {

// Lowers the calling thread's scheduling priority by `niceIncrement` (Linux: the thread's own nice
// value, up to 19; threads it starts inherit it). Returns false where that cannot be done (another
// system, or refused), which changes only the timing, never a result.
bool yieldToRealTime(int niceIncrement = 10);

}  // namespace bcassim
