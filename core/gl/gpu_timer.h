#pragma once
// GPU time of a stretch of GL commands, from two GL_TIMESTAMP queries.
// (GL_TIME_ELAPSED would do on NVIDIA, but llvmpipe loses its start when the
// commands switch framebuffers, as a shadow pass does.)

#include <GL/glcorearb.h>

namespace loom::gl {

class GpuTimer {
 public:
  GpuTimer();
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  void Start();
  void Stop();
  // Waits for the GPU to reach Stop().
  double Milliseconds() const;

 private:
  GLuint queries_[2] = {};
};

}  // namespace loom::gl
