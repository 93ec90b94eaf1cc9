#include "apps/safe_stderr.h"

#include <iostream>
#include <streambuf>

namespace slam {
namespace {

class ControlByteFilter : public std::streambuf {
 public:
  explicit ControlByteFilter(std::streambuf* target) : target_(target) {}

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return 0;
    return target_->sputc(Safe(traits_type::to_char_type(c)));
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    for (std::streamsize i = 0; i < n; ++i) {
      if (traits_type::eq_int_type(target_->sputc(Safe(s[i])),
                                   traits_type::eof())) {
        return i;
      }
    }
    return n;
  }
  int sync() override { return target_->pubsync(); }

 private:
  static char Safe(char c) {
    const unsigned char u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\n' && c != '\t') || u == 0x7f ? '?' : c;
  }

  std::streambuf* target_;
};

}  // namespace

void FilterControlBytesOnStderr() {
  // Lives as long as the process (std::cerr may be used until exit).
  static ControlByteFilter* filter = new ControlByteFilter(std::cerr.rdbuf());
  std::cerr.rdbuf(filter);
}

}  // namespace slam
