/* Preloaded in front of Oclgrind's runtime by scripts/oclgrind.sh: works around
 * two bugs in the global-memory bookkeeping of Oclgrind 21.10's --uninitialized
 * checker (plugins/MemCheckUninitialized.cpp) that otherwise report correct
 * kernels. Each was reproduced with a 40-line host program (the script's
 * comment lists them); neither touches what a kernel does, so every check of
 * kernel code stays as Oclgrind has it.
 *
 * 1. Released buffers keep their shadow. Oclgrind reuses a released buffer's
 *    index for the next allocation, and the checker keeps the old buffer's
 *    shadow (it has no memoryDeallocated hook). A new, larger buffer that
 *    kernels write and then read is reported uninitialized past the old size
 *    (its shadow stores there are dropped). Fix: a release that would free a
 *    buffer does not reach Oclgrind, so every buffer gets a fresh index (the
 *    memory stays allocated until exit; the tests under Oclgrind are small).
 *
 * 2. A host store that is not the whole buffer from offset 0 replaces the
 *    buffer's shadow with one of the store's size (ShadowMemory::allocate), so
 *    the rest of the buffer reads as uninitialized; fills store pattern by
 *    pattern (each one replaces it again), copies count as host stores, and
 *    buffers created from host memory or written through a map get no shadow
 *    at all (poisoned at the next launch). Fix: after each such command, read
 *    the whole buffer back and write it whole from offset 0, which gives it a
 *    clean shadow of the right size. Such buffers then count as initialized
 *    everywhere (the host wrote them); buffers only kernels write keep exact
 *    tracking.
 *
 * Only cl_mem buffers are handled (no images or sub-buffers: the kernels
 * checked under Oclgrind use neither). */
#define _GNU_SOURCE
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

#define NEXT(name) ((__typeof__(&name))next_symbol(#name))

static void* next_symbol(const char* name) {
  void* f = dlsym(RTLD_NEXT, name);
  if (!f) {
    fprintf(stderr, "oclgrind_shadow_fix: %s not found behind the shim\n", name);
    abort();
  }
  return f;
}

static void check(cl_int err, const char* what) {
  if (err != CL_SUCCESS) {
    fprintf(stderr, "oclgrind_shadow_fix: %s failed (%d)\n", what, err);
    abort();
  }
}

/* Rewrites all of `mem` from offset 0 through `queue` (blocking). */
static void refresh(cl_command_queue queue, cl_mem mem) {
  size_t size = 0;
  check(clGetMemObjectInfo(mem, CL_MEM_SIZE, sizeof size, &size, NULL), "clGetMemObjectInfo");
  void* bytes = malloc(size ? size : 1);
  if (!bytes) abort();
  check(NEXT(clEnqueueReadBuffer)(queue, mem, CL_TRUE, 0, size, bytes, 0, NULL, NULL), "read for refresh");
  check(NEXT(clEnqueueWriteBuffer)(queue, mem, CL_TRUE, 0, size, bytes, 0, NULL, NULL), "write for refresh");
  free(bytes);
}

cl_int clReleaseMemObject(cl_mem mem) {
  cl_uint refs = 0;
  cl_mem_object_type type = 0;
  if (clGetMemObjectInfo(mem, CL_MEM_REFERENCE_COUNT, sizeof refs, &refs, NULL) == CL_SUCCESS &&
      clGetMemObjectInfo(mem, CL_MEM_TYPE, sizeof type, &type, NULL) == CL_SUCCESS && refs == 1 &&
      type == CL_MEM_OBJECT_BUFFER)
    return CL_SUCCESS; /* keep it: its index must not be reused (bug 1) */
  return NEXT(clReleaseMemObject)(mem);
}

cl_mem clCreateBuffer(cl_context context, cl_mem_flags flags, size_t size, void* host_ptr, cl_int* err) {
  cl_mem mem = NEXT(clCreateBuffer)(context, flags, size, host_ptr, err);
  if (mem && (flags & (CL_MEM_USE_HOST_PTR | CL_MEM_COPY_HOST_PTR))) {
    cl_device_id device;
    check(clGetContextInfo(context, CL_CONTEXT_DEVICES, sizeof device, &device, NULL), "clGetContextInfo");
    cl_int e = CL_SUCCESS;
    cl_command_queue q = clCreateCommandQueue(context, device, 0, &e);
    check(e, "clCreateCommandQueue");
    refresh(q, mem);
    clReleaseCommandQueue(q);
  }
  return mem;
}

cl_int clEnqueueWriteBuffer(cl_command_queue q, cl_mem mem, cl_bool blocking, size_t offset, size_t size,
                            const void* ptr, cl_uint nwait, const cl_event* wait, cl_event* event) {
  cl_int e = NEXT(clEnqueueWriteBuffer)(q, mem, blocking, offset, size, ptr, nwait, wait, event);
  size_t total = 0;
  if (e == CL_SUCCESS && clGetMemObjectInfo(mem, CL_MEM_SIZE, sizeof total, &total, NULL) == CL_SUCCESS &&
      (offset != 0 || size != total))
    refresh(q, mem);
  return e;
}

cl_int clEnqueueWriteBufferRect(cl_command_queue q, cl_mem mem, cl_bool blocking, const size_t* buffer_origin,
                                const size_t* host_origin, const size_t* region, size_t buffer_row_pitch,
                                size_t buffer_slice_pitch, size_t host_row_pitch, size_t host_slice_pitch,
                                const void* ptr, cl_uint nwait, const cl_event* wait, cl_event* event) {
  cl_int e = NEXT(clEnqueueWriteBufferRect)(q, mem, blocking, buffer_origin, host_origin, region, buffer_row_pitch,
                                            buffer_slice_pitch, host_row_pitch, host_slice_pitch, ptr, nwait, wait,
                                            event);
  if (e == CL_SUCCESS) refresh(q, mem);
  return e;
}

cl_int clEnqueueFillBuffer(cl_command_queue q, cl_mem mem, const void* pattern, size_t pattern_size, size_t offset,
                           size_t size, cl_uint nwait, const cl_event* wait, cl_event* event) {
  cl_int e = NEXT(clEnqueueFillBuffer)(q, mem, pattern, pattern_size, offset, size, nwait, wait, event);
  if (e == CL_SUCCESS) refresh(q, mem);
  return e;
}

cl_int clEnqueueCopyBuffer(cl_command_queue q, cl_mem src, cl_mem dst, size_t src_offset, size_t dst_offset,
                           size_t size, cl_uint nwait, const cl_event* wait, cl_event* event) {
  cl_int e = NEXT(clEnqueueCopyBuffer)(q, src, dst, src_offset, dst_offset, size, nwait, wait, event);
  if (e == CL_SUCCESS) refresh(q, dst);
  return e;
}

cl_int clEnqueueCopyBufferRect(cl_command_queue q, cl_mem src, cl_mem dst, const size_t* src_origin,
                               const size_t* dst_origin, const size_t* region, size_t src_row_pitch,
                               size_t src_slice_pitch, size_t dst_row_pitch, size_t dst_slice_pitch, cl_uint nwait,
                               const cl_event* wait, cl_event* event) {
  cl_int e = NEXT(clEnqueueCopyBufferRect)(q, src, dst, src_origin, dst_origin, region, src_row_pitch,
                                           src_slice_pitch, dst_row_pitch, dst_slice_pitch, nwait, wait, event);
  if (e == CL_SUCCESS) refresh(q, dst);
  return e;
}

/* Maps with write access: the pointer and buffer, refreshed at unmap. */
#define MAX_MAPS 256
static struct {
  void* ptr;
  cl_mem mem;
} maps[MAX_MAPS];
static pthread_mutex_t maps_lock = PTHREAD_MUTEX_INITIALIZER;

void* clEnqueueMapBuffer(cl_command_queue q, cl_mem mem, cl_bool blocking, cl_map_flags flags, size_t offset,
                         size_t size, cl_uint nwait, const cl_event* wait, cl_event* event, cl_int* err) {
  void* p = NEXT(clEnqueueMapBuffer)(q, mem, blocking, flags, offset, size, nwait, wait, event, err);
  if (p && (flags & (CL_MAP_WRITE | CL_MAP_WRITE_INVALIDATE_REGION))) {
    pthread_mutex_lock(&maps_lock);
    int i = 0;
    while (i < MAX_MAPS && maps[i].ptr) ++i;
    if (i == MAX_MAPS) {
      fprintf(stderr, "oclgrind_shadow_fix: more than %d buffers mapped for writing\n", MAX_MAPS);
      abort();
    }
    maps[i].ptr = p;
    maps[i].mem = mem;
    pthread_mutex_unlock(&maps_lock);
  }
  return p;
}

cl_int clEnqueueUnmapMemObject(cl_command_queue q, cl_mem mem, void* ptr, cl_uint nwait, const cl_event* wait,
                               cl_event* event) {
  cl_int e = NEXT(clEnqueueUnmapMemObject)(q, mem, ptr, nwait, wait, event);
  int written = 0;
  pthread_mutex_lock(&maps_lock);
  for (int i = 0; i < MAX_MAPS; ++i)
    if (maps[i].ptr == ptr && maps[i].mem == mem) {
      maps[i].ptr = NULL;
      written = 1;
      break;
    }
  pthread_mutex_unlock(&maps_lock);
  if (e == CL_SUCCESS && written) refresh(q, mem);
  return e;
}
