// Used by tests/gl/gbuffer_normal_test.cpp: the G-buffer's octahedral encoding
// with the RG16 unorm store in between: packed_out[i] = the two 16-bit values,
// decoded[i] = the normal the deferred pass sees.
layout(local_size_x = 64) in;
#include "common/octahedral.glsl"
#include "test_shader_bindings.h"
layout(std430, binding = ML_BINDING_TEST_OCTAHEDRAL_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = ML_BINDING_TEST_OCTAHEDRAL_PACKED) writeonly buffer Packed { uint packed_out[]; };
layout(std430, binding = ML_BINDING_TEST_OCTAHEDRAL_DECODED) writeonly buffer Decoded { vec4 decoded[]; };
uniform uint u_n;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_n) return;
  uint p = packUnorm2x16(octEncode(normals[i].xyz));
  packed_out[i] = p;
  decoded[i] = vec4(octDecode(unpackUnorm2x16(p)), 0.0);
}
