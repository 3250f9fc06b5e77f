// tinygltf and stb_image compiled into the fuzz build from the same Debian
// headers the product's libtinygltf was built from, so that the sanitizers
// and the fuzzer's coverage see inside the glTF parser too.
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
