#include "core/gl/gpu_timer.h"

namespace loom::gl {

GpuTimer::GpuTimer() { glCreateQueries(GL_TIMESTAMP, 2, queries_); }

GpuTimer::~GpuTimer() { glDeleteQueries(2, queries_); }

// llvmpipe bins a frame's commands and runs them, timestamps included, at the next
// flush: a start stamp binned with the draws is taken as they run, and the timer
// read 0 for a frame drawn into the framebuffer the last one used. The flush sends
// the stamp on its own; to a GPU it only submits what is queued.
void GpuTimer::Start() {
  glQueryCounter(queries_[0], GL_TIMESTAMP);
  glFlush();
}

void GpuTimer::Stop() { glQueryCounter(queries_[1], GL_TIMESTAMP); }

double GpuTimer::Milliseconds() const {
  GLuint64 start_ns = 0, stop_ns = 0;
  glGetQueryObjectui64v(queries_[0], GL_QUERY_RESULT, &start_ns);
  glGetQueryObjectui64v(queries_[1], GL_QUERY_RESULT, &stop_ns);
  return stop_ns > start_ns ? static_cast<double>(stop_ns - start_ns) * 1e-6 : 0.0;
}

}  // namespace loom::gl
