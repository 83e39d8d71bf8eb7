// Fuzz target: the command line. The bytes are the arguments (one per line, at most 64); they are parsed onto
// the options structs as `rtsdf` parses them (bindCommands) and the chosen command's options are checked as its
// job checks them first, without running it. Any arguments must parse or give CLI11's error or an rtsdf::Error.
#include "Options.h"

#include "util/Error.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace {

void checkChosen(const rtsdf::app::Commands& c, const std::string& which) {
  if (which == "bake") c.bake.options.validate();
  else if (which == "animate") c.animate.options.validate();
  else if (which == "render") c.render.options.validate();
  else if (which == "view") c.view.validate();
  else if (which == "compare") c.compare.options.validate();
  else if (which == "bench") c.bench.sweep.empty() ? c.bench.suite.validate() : c.bench.sweepOptions.validate();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"rtsdf"};
  std::string word;
  for (std::size_t i = 0; i < size && args.size() < 64; ++i) {
    if (data[i] == '\n') {
      args.push_back(word);
      word.clear();
    } else {
      word += char(data[i]);
    }
  }
  if (!word.empty() && args.size() < 64) args.push_back(word);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());

  rtsdf::app::Commands commands;
  CLI::App app{"rtsdf"};
  int verbosity = 0;
  bool quiet = false;
  rtsdf::app::bindCommands(app, commands, verbosity, quiet);
  try {
    app.parse(int(argv.size()), argv.data());
  } catch (const CLI::Error&) {
    return 0;
  }
  if (app.get_subcommands().empty()) return 0;
  const std::string which = app.get_subcommands().front()->get_name();
  try {
    checkChosen(commands, which);
  } catch (const rtsdf::SettingError& e) {
    (void)commands.flags.flagOf(e.setting()); // what main prints with it
  } catch (const rtsdf::Error&) {
  }
  return 0;
}
