// Used by the SharedBuffer tests: dst[i] = src[i] ^ key, on the GL side.
#include "test_shader_bindings.h"
layout(local_size_x = 64) in;
layout(std430, binding = ML_BINDING_TEST_XOR_SRC) readonly buffer Src { uint src[]; };
layout(std430, binding = ML_BINDING_TEST_XOR_DST) writeonly buffer Dst { uint dst[]; };
uniform uint u_key;
uniform uint u_n;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < u_n) dst[i] = src[i] ^ u_key;
}
