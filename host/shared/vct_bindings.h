/* Binding points of the voxel cone tracing GL passes, numbered once for C++
 * and GLSL (as shading_bindings.h does for the shading programs):
 * voxelize.frag, voxel_view.comp, vct_cones.glsl, vct_trace.comp and
 * vct_upsample.comp declare their buffers, images and samplers with these
 * names (GLSL includes this file as "vct_bindings.h"), and VoxelizePass,
 * VoxelView, ConeTracing and VctGiPass bind with them. Each program has its
 * own numbering; numbers repeat across programs. Plain macros: the one form
 * that C++, OpenCL C and GLSL all read. */
#ifndef MANYLIGHTS_VCT_BINDINGS_H
#define MANYLIGHTS_VCT_BINDINGS_H

#include "shading_bindings.h"

/* Voxelization: the accumulation buffer (VoxelAccum[], voxel_types.h). */
#define ML_BINDING_VOXELIZE_ACCUM 0

/* A region of a voxel grid (host/vct/VoxelRegion.hpp) has at most this many
 * boxes: a scrolled cascade level's slab per axis, and the box a finer
 * level's window left (CascadeFold.hpp). voxelize.geom and .frag size their
 * box uniforms with it. */
#define ML_VOXEL_REGION_BOXES 4

/* Second bounce (vct_bounce.comp): level 0's sums and the radiance volume;
 * the cones' textures take the trace's units (ML_UNIT_VCT_VOXELS ..). */
#define ML_BINDING_BOUNCE_ACCUM 0
#define ML_BINDING_BOUNCE_RADIANCE 1
#define ML_VOXEL_ALBEDO_SCALE_GLSL 255 /* ML_VOXEL_ALBEDO_SCALE (voxel_types.h), which GLSL does not include */

/* Voxel view: the volume's buffers and the output image. */
#define ML_BINDING_VOXEL_VIEW_RADIANCE 0 /* every level */
#define ML_BINDING_VOXEL_VIEW_ACCUM 1    /* level 0 */
#define ML_BINDING_VOXEL_VIEW_ANISO 2    /* levels >= 1, 6 directions */
#define ML_IMAGE_VOXEL_VIEW_OUT 0

/* Texture units of the trace and upsample passes: the G-buffer (the units
 * deferred shading reads it from), the voxel textures of the cones and the
 * upsample's reduced-resolution inputs. The cones read ML_VCT_MAX_LEVELS
 * cascade levels (a shader define, 1 unless the program sets it): level c's
 * radiance at ML_UNIT_VCT_VOXELS + c, its 6 direction textures from
 * ML_UNIT_VCT_VOXEL_DIRS + 6 c (host/vct/ConeTracing.cpp: the same units). */
#ifndef ML_VCT_MAX_LEVELS
#define ML_VCT_MAX_LEVELS 1
#endif
#define ML_UNIT_VCT_GBUFFER_ALBEDO ML_UNIT_GBUFFER_ALBEDO
#define ML_UNIT_VCT_GBUFFER_NORMAL ML_UNIT_GBUFFER_NORMAL
#define ML_UNIT_VCT_GBUFFER_DEPTH ML_UNIT_GBUFFER_DEPTH
#define ML_UNIT_VCT_VOXELS 4
#define ML_UNIT_VCT_VOXEL_DIRS (ML_UNIT_VCT_VOXELS + ML_VCT_MAX_LEVELS)
#define ML_UNIT_VCT_LO_IRRADIANCE 4
#define ML_UNIT_VCT_LO_GEOMETRY 5
#define ML_UNIT_VCT_LO_SPECULAR 6

/* Images the trace writes at reduced resolution. */
#define ML_IMAGE_VCT_TRACE_IRRADIANCE 0
#define ML_IMAGE_VCT_TRACE_GEOMETRY 1
#define ML_IMAGE_VCT_TRACE_SPECULAR 2

/* Images of the upsample: the shaded frame (read and added to), the indirect
 * light and the ambient occlusion. */
#define ML_IMAGE_VCT_UPSAMPLE_COLOR 0
#define ML_IMAGE_VCT_UPSAMPLE_INDIRECT 1
#define ML_IMAGE_VCT_UPSAMPLE_AO 2

/* Tests only (gl/shaders/test/test_vct_cones.comp, tests/vct/vct_furnace_test.cpp):
 * the points and normals traceDiffuse runs at, and its results. */
#define ML_BINDING_TEST_CONES_POINTS 1
#define ML_BINDING_TEST_CONES_NORMALS 2
#define ML_BINDING_TEST_CONES_RESULTS 3

#endif
