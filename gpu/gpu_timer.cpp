#include "gpu/gpu_timer.h"

#include <sys/resource.h>

#include <stdexcept>

namespace ft {

GpuTimer::GpuTimer(const GlInfo& info, Method method)
    : useQueries_(method == Method::TimeElapsedQuery ||
                  (method == Method::Auto && info.timerQueriesMeaningful)) {
  if (useQueries_) query_ = Query::create(GL_TIME_ELAPSED);
}

void GpuTimer::begin() {
  if (running_) throw std::logic_error("GpuTimer::begin: region already running");
  running_ = true;
  if (useQueries_) {
    glBeginQuery(GL_TIME_ELAPSED, query_.id());
    glCheck("GpuTimer::begin (glBeginQuery)");
  } else {
    glFinish();  // earlier work must not count
    start_ = std::chrono::steady_clock::now();
  }
}

double GpuTimer::endMs() {
  if (!running_) throw std::logic_error("GpuTimer::endMs: no region running");
  running_ = false;
  if (useQueries_) {
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query_.id(), GL_QUERY_RESULT, &ns);  // waits for the result
    glCheck("GpuTimer::endMs (glGetQueryObjectui64v)");
    return static_cast<double>(ns) * 1e-6;
  }
  glFinish();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
}

const char* GpuTimer::method() const { return useQueries_ ? "GL_TIME_ELAPSED" : "glFinish+steady_clock"; }

double processCpuMs() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0.0;
  return 1e3 * double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-3 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace ft
