#include "library_messages.hpp"

#include <itkOutputWindow.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <mutex>
#include <sstream>

namespace stvd::imaging::detail {
namespace {

std::recursive_mutex& captureLock() {
  static std::recursive_mutex lock;
  return lock;
}

/// Text of the active captures; ITK's output window writes into it.
std::ostringstream& collected() {
  static std::ostringstream text;
  return text;
}
int depth = 0;

/// ITK's output window: into the capture while one is active, to standard
/// error otherwise (as ITK's own window does).
class CollectingOutputWindow : public itk::OutputWindow {
 public:
  ITK_DISALLOW_COPY_AND_MOVE(CollectingOutputWindow);
  using Self = CollectingOutputWindow;
  using Pointer = itk::SmartPointer<Self>;
  static Pointer New() {
    Pointer p = new Self;
    p->UnRegister();
    return p;
  }
  void DisplayText(const char* text) override {
    std::lock_guard<std::recursive_mutex> guard(captureLock());
    if (depth > 0)
      collected() << text << '\n';
    else
      std::fputs(text, stderr);
  }

 protected:
  CollectingOutputWindow() = default;
};

void installOutputWindow() {
  static std::once_flag once;
  std::call_once(once, [] { itk::OutputWindow::SetInstance(CollectingOutputWindow::New()); });
}

}  // namespace

struct LibraryMessageCapture::State {
  std::unique_lock<std::recursive_mutex> guard{captureLock()};
  int savedFd = -1;
  std::FILE* sink = nullptr;
  std::streambuf* savedCerr = nullptr;
  std::ostringstream cerrText;
  std::size_t start = 0;
};

LibraryMessageCapture::LibraryMessageCapture() : state_(new State) {
  installOutputWindow();
  State& s = *state_;
  s.start = collected().str().size();
  if (depth++ > 0) return;  // the outer capture diverts the streams already
  std::fflush(stderr);
  std::cerr.flush();
  s.sink = std::tmpfile();
  if (s.sink) {
    s.savedFd = ::dup(2);
    if (s.savedFd < 0 || ::dup2(::fileno(s.sink), 2) < 0) {
      if (s.savedFd >= 0) ::close(s.savedFd);
      s.savedFd = -1;
    }
  }
  s.savedCerr = std::cerr.rdbuf(s.cerrText.rdbuf());
}

LibraryMessageCapture::~LibraryMessageCapture() {
  State& s = *state_;
  if (--depth > 0) return;
  std::cerr.rdbuf(s.savedCerr);
  std::fflush(stderr);
  if (s.savedFd >= 0) {
    ::dup2(s.savedFd, 2);
    ::close(s.savedFd);
  }
  if (s.sink) std::fclose(s.sink);
  collected().str("");
}

std::string LibraryMessageCapture::text() {
  State& s = *state_;
  std::string all = collected().str().substr(s.start);
  std::fflush(stderr);
  if (depth > 0 && s.sink) {  // what went to file descriptor 2
    std::rewind(s.sink);
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, s.sink)) > 0) all.append(buffer, n);
    std::fseek(s.sink, 0, SEEK_END);
  }
  all += s.cerrText.str();
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
