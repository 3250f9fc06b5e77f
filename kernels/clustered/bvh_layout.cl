/* The light BVH's memory layout, the contract between the kernels that
 * build it (clustered/light_bvh.cl) and the assignment that walks it
 * (clustered/cluster_assign.cl); the host (ClusterLightAssigner) sizes the
 * buffers from the same numbers.
 *
 *   leaves   LEAF_SIZE lights per leaf as structure of arrays: LEAF_SIZE x,
 *            then y, distance -z, r^2 (1 + 4 DEPTH_EPS); padding lights
 *            have r^2 = -1 and never hit
 *   nodes    each level's node boxes and bounding spheres in blocks of
 *            BVH_BRANCH siblings, NODE_FLOATS arrays of BVH_BRANCH floats:
 *            lo.xyz, hi.xyz, sphere xyzr; the children of node i of level
 *            l + 1 are block i of level l
 */
#ifndef ML_CLUSTERED_BVH_LAYOUT_CL
#define ML_CLUSTERED_BVH_LAYOUT_CL

#define BVH_BRANCH 32u
/* Lights per leaf (host: ClusterLightAssigner's leaf size). Leaves are tested
 * whole in one branch-free loop; small leaves (8: one AVX vector) test fewer
 * lights that miss, wide ones suit a GPU's SIMD width. */
#ifndef LEAF_SIZE
#define LEAF_SIZE 32u
#endif
/* Per BVH node in a sibling block: box lo.xyz, hi.xyz, bounding sphere xyzr. */
#define NODE_FLOATS 10u

#endif /* ML_CLUSTERED_BVH_LAYOUT_CL */
