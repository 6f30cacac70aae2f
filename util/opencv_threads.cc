#include "util/opencv_threads.h"

#include <mutex>
#include <opencv2/core/utility.hpp>

namespace calibench {

void UseSequentialOpenCv() {
  static std::once_flag once;
  std::call_once(once, [] { cv::setNumThreads(0); });
}

}  // namespace calibench
