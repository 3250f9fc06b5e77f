/* Binding points of the shading programs, numbered once for C++ and GLSL:
 * gl/shaders/common/common.glsl and the lookup_*.glsl files declare their buffers,
 * material.glsl and deferred.frag their samplers, with these names (GLSL
 * includes this file as "shading_bindings.h"), and FrameRenderer, SceneGpu
 * and the assigners bind with them. Shader storage: 0 and 7 are the frame's;
 * 1..6 belong to the technique whose lookup is compiled in, so techniques
 * share the numbers. Plain macros: the one form that C++, OpenCL C and GLSL
 * all read. */
#ifndef MANYLIGHTS_SHADING_BINDINGS_H
#define MANYLIGHTS_SHADING_BINDINGS_H

#define ML_BINDING_LIGHTS 0 /* PointLight[] (gpu_types.h) */
#define ML_BINDING_STATS 7  /* light-evaluation counters, with COUNT_LIGHTS */

/* Tiled shading: the light index list and each tile's (offset, count). */
#define ML_BINDING_TILED_INDICES 1
#define ML_BINDING_TILED_GRID 2

/* Clustered shading: hit records, each cluster's record range, the per-pixel
 * cluster map and the leaves' light slots. */
#define ML_BINDING_CLUSTER_RECORDS 1
#define ML_BINDING_CLUSTER_RANGES 2
#define ML_BINDING_CLUSTER_MAP 3
#define ML_BINDING_CLUSTER_LEAF_LIGHTS 4

/* Hashed shading: the light index list, the octree header, and the perfect
 * spatial hashes' offset, description and light-data tables. */
#define ML_BINDING_HASHED_INDICES 1
#define ML_BINDING_HASHED_HEADER 2
#define ML_BINDING_HASHED_OFFSETS 3
#define ML_BINDING_HASHED_DESC 4
#define ML_BINDING_HASHED_DATA 5

/* Texture units: the material's base-colour texture (every geometry pass) and
 * the G-buffer that deferred shading reads (gl/RenderTargets). */
#define ML_UNIT_BASE_TEXTURE 0
#define ML_UNIT_GBUFFER_ALBEDO 1
#define ML_UNIT_GBUFFER_NORMAL 2
#define ML_UNIT_GBUFFER_DEPTH 3

#endif
