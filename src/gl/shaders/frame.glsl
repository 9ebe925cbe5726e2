// The per-frame block every stage reads (GpuFrame, gpu_shared.h) and shared constants.
layout(std140, binding = kFrameBinding) uniform Frame { GpuFrame frame; };
const float kTwoPi = 6.283185307179586;
const float kHalfPi = 1.5707963267948966;
