// Boost.Compute's sort on our OpenCL queue and buffer, in its own translation
// unit so that Boost.Compute's CL includes and macros stay away from the rest.
#include <boost/compute/algorithm/sort.hpp>
#include <boost/compute/command_queue.hpp>
#include <boost/compute/container/vector.hpp>
#include <boost/compute/iterator/buffer_iterator.hpp>

#include <cstddef>

namespace ml::bench {

void boostComputeSortU32(cl_command_queue queue, cl_mem buffer, std::size_t n) {
  // retain=true: the wrappers add a reference, so ours stay valid.
  boost::compute::command_queue q(queue, true);
  boost::compute::buffer buf(buffer, true);
  auto first = boost::compute::make_buffer_iterator<cl_uint>(buf, 0);
  boost::compute::sort(first, first + static_cast<std::ptrdiff_t>(n), q);
  q.finish();
}

}  // namespace ml::bench
