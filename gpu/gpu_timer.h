// gpu_timer.h — times a GPU region. Software renderers (llvmpipe) fake
// GL_TIME_ELAPSED from CPU timestamps, so there: glFinish + steady_clock; on real
// GPUs: GL_TIME_ELAPSED queries. Reports must say which (method()).
#pragma once
#include <epoxy/gl.h>

#include <chrono>

#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

class GpuTimer {
 public:
  enum class Method { Auto, FinishClock, TimeElapsedQuery };

  // Auto picks TimeElapsedQuery when info.timerQueriesMeaningful, else FinishClock.
  explicit GpuTimer(const GlInfo& info, Method method = Method::Auto);

  // Starts a region; GL commands issued until end() are timed. No nesting
  // (GL_TIME_ELAPSED queries cannot nest).
  void begin();
  // Ends the region and returns its GPU time in milliseconds (waits for the GPU).
  double endMs();

  // "glFinish+steady_clock" or "GL_TIME_ELAPSED".
  const char* method() const;
  bool usesQueries() const { return useQueries_; }

 private:
  bool useQueries_;
  bool running_ = false;
  Query query_;
  std::chrono::steady_clock::time_point start_;
};

// CPU time of this process, all threads, in milliseconds (getrusage: user +
// system). On llvmpipe the frame is CPU work; on a machine shared with other
// jobs its wall time varies by 2x with their load, its CPU time far less, so
// profiles quote both (docs/shaded-frame.md).
double processCpuMs();

}  // namespace ft
