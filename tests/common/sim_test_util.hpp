// Helpers shared by the tests that drive the SIL engine or the dtc-sim
// command line: scenario loading through the library API, running a command
// with its exit status, and (temp_files.hpp) temporary directories and files.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "sim/scenario.h"
#include "sim/sim.h"
#include "temp_files.hpp"

namespace simtest {

// Scenarios are a few kB; keep them off the stack.
using ScenarioPtr = std::unique_ptr<scenario>;

struct Loaded {
    ScenarioPtr sc;
    int rc = 0;        // 0 or SCENARIO_EINPUT
    std::string error; // the one-line message when rc != 0
};

// Defaults, then @p parse (file or text), then @p sets ("section.key=value"),
// then finish, as dtc-sim does.
template <typename Parse>
inline Loaded load_with(Parse parse, const std::vector<std::string> &sets)
{
    Loaded l;
    l.sc = std::make_unique<scenario>();
    char err[2048] = "";
    scenario_default(l.sc.get());
    l.rc = parse(l.sc.get(), err, sizeof err);
    for (size_t i = 0; l.rc == 0 && i < sets.size(); ++i)
        l.rc = scenario_set(l.sc.get(), sets[i].c_str(), err, sizeof err);
    if (l.rc == 0)
        l.rc = scenario_finish(l.sc.get(), err, sizeof err);
    l.error = err;
    return l;
}

// Parse @p path, apply @p sets and finish, as dtc-sim does.
inline Loaded load_scenario(const std::string &path, const std::vector<std::string> &sets = {})
{
    return load_with([&](scenario *sc, char *err, size_t n) { return scenario_parse_file(sc, path.c_str(), err, n); },
                     sets);
}

// The same from INI text; @p name plays the file name in messages.
inline Loaded parse_text(const std::string &text, const std::vector<std::string> &sets = {},
                         const std::string &name = "t.ini")
{
    return load_with(
        [&](scenario *sc, char *err, size_t n) {
            return scenario_parse_string(sc, name.c_str(), text.c_str(), err, n);
        },
        sets);
}

inline std::string source_path(const std::string &rel) { return std::string(DTC_SOURCE_DIR) + "/" + rel; }

struct CommandResult {
    int status = -1;    // exit status, or -1 if it did not exit normally
    std::string output; // stdout and stderr together
};

// Run @p cmd through the shell, capturing stdout and stderr.
inline CommandResult run_command(const std::string &cmd)
{
    CommandResult r;
    FILE *p = popen((cmd + " 2>&1").c_str(), "r");
    if (p == nullptr)
        return r;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0)
        r.output.append(buf, n);
    int st = pclose(p);
    if (st != -1 && WIFEXITED(st))
        r.status = WEXITSTATUS(st);
    return r;
}

} // namespace simtest
