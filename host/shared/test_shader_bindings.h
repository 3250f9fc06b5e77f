/* Binding points of the test-only GL compute programs, numbered once for C++
 * and GLSL (as shading_bindings.h does for the renderer's programs):
 * gl/shaders/test/test_xor.comp (tests/gl/gl_shared_buffer_test.cpp: dst = src ^ key)
 * and gl/shaders/test/test_octahedral.comp (tests/gl/gbuffer_normal_test.cpp: the
 * G-buffer normal encoding). Each program has its own numbering. */
#ifndef MANYLIGHTS_TEST_SHADER_BINDINGS_H
#define MANYLIGHTS_TEST_SHADER_BINDINGS_H

#define ML_BINDING_TEST_XOR_SRC 0
#define ML_BINDING_TEST_XOR_DST 1

#define ML_BINDING_TEST_OCTAHEDRAL_NORMALS 0
#define ML_BINDING_TEST_OCTAHEDRAL_PACKED 1
#define ML_BINDING_TEST_OCTAHEDRAL_DECODED 2

#endif
