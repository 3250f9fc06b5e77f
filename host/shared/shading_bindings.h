/* Shader-storage binding points of the shading programs, numbered once for
 * C++ and GLSL: gl/shaders/common.glsl, lookup_tiled.glsl and
 * lookup_clustered.glsl declare their buffers with these names (GLSL includes
 * this file as "shading_bindings.h"), and FrameRenderer and the assigners bind
 * with them. 0 and 7 are the frame's; 1..6 belong to the technique whose
 * lookup is compiled in, so techniques share the numbers. Plain macros: the
 * one form that C++, OpenCL C and GLSL all read. */
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

#endif
