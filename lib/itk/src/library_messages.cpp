#include "library_messages.hpp"

#include <itkOutputWindow.h>

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <string>

#include "stvd/itk/itk_messages.hpp"

namespace stvd::imaging::detail {
namespace {

/// The text collected by the captures active on this thread, and how deeply
/// they nest.
struct ThreadCapture {
  int depth = 0;
  std::string text;
};
thread_local ThreadCapture threadCapture;

/// stvd's output window: the text of a thread inside a capture is
/// collected, every other thread's goes to the window installed before.
class FilteringOutputWindow : public itk::OutputWindow {
 public:
  ITK_DISALLOW_COPY_AND_MOVE(FilteringOutputWindow);
  using Self = FilteringOutputWindow;
  using Pointer = itk::SmartPointer<Self>;
  static Pointer New(itk::OutputWindow::Pointer previous) {
    Pointer p = new Self(std::move(previous));
    p->UnRegister();
    return p;
  }

  void DisplayText(const char* text) override {
    if (!collect(text)) previous_->DisplayText(text);
  }
  void DisplayErrorText(const char* text) override {
    if (!collect(text)) previous_->DisplayErrorText(text);
  }
  void DisplayWarningText(const char* text) override {
    if (!collect(text)) previous_->DisplayWarningText(text);
  }
  void DisplayGenericOutputText(const char* text) override {
    if (!collect(text)) previous_->DisplayGenericOutputText(text);
  }
  void DisplayDebugText(const char* text) override {
    if (!collect(text)) previous_->DisplayDebugText(text);
  }

 private:
  explicit FilteringOutputWindow(itk::OutputWindow::Pointer previous) : previous_(std::move(previous)) {}
  static bool collect(const char* text) {
    if (threadCapture.depth == 0) return false;
    threadCapture.text += text;
    threadCapture.text += '\n';
    return true;
  }
  const itk::OutputWindow::Pointer previous_;
};

}  // namespace

LibraryMessageCapture::LibraryMessageCapture() {
  if (threadCapture.depth++ == 0) threadCapture.text.clear();
  start_ = threadCapture.text.size();
}

LibraryMessageCapture::~LibraryMessageCapture() {
  if (--threadCapture.depth == 0) threadCapture.text.clear();
}

std::string LibraryMessageCapture::text() const {
  const std::string all = threadCapture.text.substr(std::min(start_, threadCapture.text.size()));
  std::string line;
  bool blank = false;
  for (char c : all) {
    if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
      blank = !line.empty();
      continue;
    }
    if (blank) line += ' ';
    blank = false;
    line += c;
  }
  return line;
}

}  // namespace stvd::imaging::detail

namespace stvd::imaging {

void installItkMessageFilter() {
  static std::once_flag once;
  std::call_once(once, [] {
    itk::OutputWindow::SetInstance(detail::FilteringOutputWindow::New(itk::OutputWindow::GetInstance()));
  });
}

}  // namespace stvd::imaging
