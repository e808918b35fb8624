#include "host_sim/app/ViewWindow.hpp"

#include <opencv2/highgui.hpp>

extern "C" int carril_view_open(const char* title) {
  try {
    cv::namedWindow(title, cv::WINDOW_AUTOSIZE);
  } catch (const cv::Exception&) {
    return 1;
  }
  return 0;
}

extern "C" int carril_view_show(const char* title, int rows, int cols, const unsigned char* bgr,
                                std::size_t step) {
  const cv::Mat img(rows, cols, CV_8UC3, const_cast<unsigned char*>(bgr), step);
  cv::imshow(title, img);
  const int key = cv::waitKey(1);
  if (key == 'q' || key == 27) return 0;
  return cv::getWindowProperty(title, cv::WND_PROP_VISIBLE) >= 1.0 ? 1 : 0;
}

extern "C" void carril_view_close(void) {
  cv::destroyAllWindows();
}
