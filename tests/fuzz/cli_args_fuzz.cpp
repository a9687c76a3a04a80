// Fuzz target: the command line. The input is the argument list, one argument
// per line (argv[0] "clothbake" is added); it goes through cli::run_cli as in
// main.cpp, with Action::ParseOnly: CLI11's parsing and checks and each
// command's own value parsing (--quads A-B, fiber vectors, ...), no files.

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "cli/app.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = clothbake::fuzz::as_text(data, size);
  std::vector<std::string> args = {"clothbake"};
  for (size_t begin = 0; !text.empty() && begin <= text.size();) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    args.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  if (!text.empty() && text.back() == '\n') args.pop_back();  // no empty last argument
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  (void)clothbake::cli::run_cli(int(argv.size()), argv.data(), clothbake::cli::Action::ParseOnly,
                                out, err);
  return 0;
}
