// dtc-ident-table: the identification run against the plant for every motor
// of the table (tests/common/ident_rig.hpp), printed per motor: the true
// value, the identified one, the error in percent and the verdict, then the
// drive time of each part and the peak currents.
//
//   dtc-ident-table [--standstill] [--markdown] [--seed N] [--comp K]
//
//   --standstill  the standstill part only (Lm from the DC steps)
//   --markdown    a Markdown table (for docs/commissioning.md)
//   --seed N      the sensor noise's seed (default 1)
//   --comp K      the firmware's dead-time and drop compensation, x the plant's (default 1)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "ident_rig.hpp"

using namespace identrig;

namespace {

void usage()
{
    std::fprintf(stderr, "usage: dtc-ident-table [--standstill] [--markdown] [--seed N] [--comp K]\n");
}

struct Row {
    const char *name;
    double truth;
    ident_value found;
    double scale; // printed x this (units)
    const char *unit;
};

} // namespace

int main(int argc, char **argv)
{
    Options o;
    bool md = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--standstill")
            o.rotating = false;
        else if (a == "--markdown")
            md = true;
        else if (a == "--seed" && i + 1 < argc)
            o.seed = unsigned(std::strtoul(argv[++i], nullptr, 10));
        else if (a == "--comp" && i + 1 < argc)
            o.comp_scale = std::strtod(argv[++i], nullptr);
        else {
            usage();
            return 2;
        }
    }
    if (md) {
        std::printf("| motor | value | true | identified | error | verdict |\n|---|---|---:|---:|---:|---|\n");
    }
    int failed = 0;
    for (const Motor &m : motors()) {
        auto r = run_ident(m, o);
        const Truth t = truth_of(m);
        const ident_result &x = r->res;
        if (r->id.phase != IDENT_DONE) {
            std::printf("%s: %s (abort %d)\n", m.name.c_str(), ident_phase_name(r->id.phase), int(r->id.abort_reason));
            failed++;
            continue;
        }
        const Row rows[] = {
            {"Rs", t.rs, x.rs_ohm, 1.0, "ohm"},
            {"sigma Ls", t.sigma_ls, x.sigma_ls_H, 1e3, "mH"},
            {"Rr", t.rr, x.rr_ohm, 1.0, "ohm"},
            {"Tr", t.tr, x.tr_s, 1.0, "s"},
            {x.lm_from_rotation ? "Lm (rotating)" : "Lm (standstill)", t.lm, x.lm_H, 1e3, "mH"},
            {"J", t.J, x.j_kgm2, 1.0, "kg m2"},
            {"B", t.B, x.b_Nms, 1e3, "mN m s"},
        };
        if (!md)
            std::printf("%s\n", m.name.c_str());
        for (const Row &row : rows) {
            if (row.found.verdict == IDENT_VERDICT_NONE)
                continue;
            double e = err_pct(row.found.value, row.truth);
            if (md)
                std::printf("| %s | %s, %s | %.4g | %.4g | %+.2f %% | %s |\n", m.name.c_str(), row.name, row.unit,
                            row.truth * row.scale, double(row.found.value) * row.scale, e,
                            ident_verdict_name(row.found.verdict));
            else
                std::printf("  %-16s %-7s true %10.4g  identified %10.4g  error %+7.2f %%  %s\n", row.name, row.unit,
                            row.truth * row.scale, double(row.found.value) * row.scale, e,
                            ident_verdict_name(row.found.verdict));
        }
        if (md)
            std::printf("| %s | drive time | | standstill %.1f s, rotating %.1f s | | |\n", m.name.c_str(),
                        r->t_standstill_s, r->t_rotating_s);
        else
            std::printf("  drive time: standstill %.2f s, rotating %.2f s; peak current: standstill %.1f A "
                        "(bound %.1f A), rotating %.1f A (rated peak %.1f A)\n",
                        r->t_standstill_s, r->t_rotating_s, r->i_peak_standstill_A, double(r->ic.ss.i_max_A),
                        r->i_peak_rotating_A, rated_peak_A(m));
    }
    return failed == 0 ? 0 : 1;
}
