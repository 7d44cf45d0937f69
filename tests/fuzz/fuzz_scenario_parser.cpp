// Fuzz harness 2: the scenario parser, as dtc-sim runs it (defaults, the file,
// the --set overrides, the final checks). The input is the file's text; after
// a NUL byte, each further NUL- or newline-separated piece is one --set
// assignment. Invariants (docs/fuzzing.md): the parser returns 0 or
// SCENARIO_EINPUT and nothing else; every error is ONE line, "NAME:LINE:
// problem" with 1 <= LINE <= the lines of the text, "NAME: problem" or
// "--set KEY: problem"; an accepted scenario has its scalar values inside the
// ranges docs/scenarios.md gives; no crash, no undefined behaviour, no leak
// (the sanitizers).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include "sim/scenario.h"
}

namespace {

[[noreturn]] void violated(const std::string &what, const std::string &err)
{
    std::fprintf(stderr, "fuzz_scenario_parser: invariant violated: %s\n  message: %s\n", what.c_str(), err.c_str());
    std::abort();
}

void check_message(const std::string &err, const std::string &text)
{
    if (err.empty())
        violated("an error without a message", err);
    for (char ch : err)
        if ((unsigned char)ch < 0x20u || ch == 0x7f)
            violated("a control character (a second line) in the message", err);
    const std::string name = "fuzz.ini";
    if (err.rfind("--set ", 0) == 0) {
        if (err.find(": ") == std::string::npos)
            violated("a --set message without 'KEY: problem'", err);
        return;
    }
    if (err.rfind(name + ":", 0) != 0)
        violated("a message that names neither the file nor a --set", err);
    std::string rest = err.substr(name.size() + 1);
    if (rest.rfind(" ", 0) == 0)
        return; // "fuzz.ini: problem" (the whole file)
    size_t colon = rest.find(": ");
    if (colon == std::string::npos || colon == 0)
        violated("no 'LINE: problem' after the file name", err);
    long line = 0;
    for (size_t i = 0; i < colon; i++) {
        if (rest[i] < '0' || rest[i] > '9')
            violated("a line number that is not a number", err);
        line = line * 10 + (rest[i] - '0');
        if (line > 100000000)
            violated("an absurd line number", err);
    }
    long lines = 1;
    for (char ch : text)
        lines += ch == '\n';
    if (line < 1 || line > lines)
        violated("line " + std::to_string(line) + " outside the text's 1.." + std::to_string(lines), err);
}

void check_accepted(const scenario &sc)
{
    if (!(sc.duration_s > 0.0 && sc.duration_s <= 600.0))
        violated("duration_s " + std::to_string(sc.duration_s) + " accepted", "");
    if (!(sc.period_s >= 50e-6 && sc.period_s <= 1e-3))
        violated("period_s " + std::to_string(sc.period_s) + " accepted", "");
    if (!(sc.trace_interval_s >= sc.period_s * (1.0 - 1e-9)))
        violated("trace_interval_s below period_s accepted", "");
    if (sc.n_ref < 0 || sc.n_ref > SCENARIO_MAX_ENTRIES || sc.n_load < 0 || sc.n_load > SCENARIO_MAX_ENTRIES ||
        sc.n_events < 0 || sc.n_events > SCENARIO_MAX_ENTRIES || sc.n_faults < 0 ||
        sc.n_faults > SCENARIO_MAX_ENTRIES || sc.n_windows < 0 || sc.n_windows > SCENARIO_MAX_WINDOWS)
        violated("an entry count outside its table", "");
    for (int i = 0; i < sc.n_ref; i++)
        if (!std::isfinite(sc.ref[i].rpm) || std::fabs(sc.ref[i].rpm) > 100000.0 || sc.ref[i].t0_s < 0.0 ||
            sc.ref[i].t1_s > 600.0 || (i > 0 && sc.ref[i].t0_s < sc.ref[i - 1].t1_s))
            violated("a reference entry out of range or order accepted", "");
    for (int i = 0; i < sc.n_windows; i++)
        if (std::strlen(sc.windows[i].name) == 0 || std::strlen(sc.windows[i].name) >= SCENARIO_NAME_LEN)
            violated("a window name of a bad length accepted", "");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 64 * 1024)
        return 0; // scenarios are a few kB; longer inputs only slow the search
    const char *p = reinterpret_cast<const char *>(data);
    const char *nul = static_cast<const char *>(std::memchr(p, '\0', size));
    std::string text(p, nul != nullptr ? size_t(nul - p) : size);
    std::vector<std::string> sets;
    if (nul != nullptr) {
        std::string cur;
        for (const char *q = nul + 1; q < p + size; q++) {
            if (*q == '\0' || *q == '\n') {
                sets.push_back(cur);
                cur.clear();
            } else {
                cur.push_back(*q);
            }
        }
        sets.push_back(cur);
        if (sets.size() > 8)
            sets.resize(8);
    }
    std::unique_ptr<scenario> sc(new scenario);
    char err[2048];
    err[0] = '\0';
    scenario_default(sc.get());
    int rc = scenario_parse_string(sc.get(), "fuzz.ini", text.c_str(), err, sizeof err);
    for (size_t i = 0; rc == 0 && i < sets.size(); i++)
        rc = scenario_set(sc.get(), sets[i].c_str(), err, sizeof err);
    if (rc == 0)
        rc = scenario_finish(sc.get(), err, sizeof err);
    if (rc != 0 && rc != SCENARIO_EINPUT)
        violated("return code " + std::to_string(rc), err);
    if (rc == SCENARIO_EINPUT)
        check_message(err, text);
    else
        check_accepted(*sc);
    return 0;
}
