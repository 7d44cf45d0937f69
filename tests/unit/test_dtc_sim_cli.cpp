// The dtc-sim command line, run as a separate process: exit statuses, the
// one-line FILE:LINE messages, and that a failed run leaves no output behind
// (and never touches an older file of the same name).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <string>

#include <cJSON.h>

#include "sim_test_util.hpp"

using simtest::CommandResult;
using simtest::TempDir;

namespace {

const std::string kSim = std::string(DTC_BINARY_DIR) + "/bin/dtc-sim";

CommandResult sim(const std::string &args) { return simtest::run_command(kSim + " " + args); }

std::string q(const std::string &s) { return "'" + s + "'"; }

// Count the lines of @p s (a trailing newline does not start a new line).
int lines(const std::string &s)
{
    int n = 0;
    for (size_t i = 0; i < s.size(); ++i)
        if (s[i] == '\n' || i + 1 == s.size())
            ++n;
    return n;
}

// The 10 hp plate up to its speed (lines 1-9; n_rpm follows on line 10).
#define kPlate10hp "[ratings]\nP_W = 7457\nV_ll_V = 220\nI_A = 24.4\nf_Hz = 60\nvdc_nom_V = 311\n" \
                   "inv_I_rated_A = 30\ninv_I_peak_A = 100\n\n"

struct BadCase {
    const char *name;
    const char *text;
    int line;
    const char *what;
};

} // namespace

TEST(DtcSimCli, HelpDocumentsEveryOption)
{
    auto r = sim("--help");
    EXPECT_EQ(r.status, 0);
    for (const char *opt : { "run FILE", "bench", "--controller", "--csv", "--metrics", "--set", "--realtime",
                             "--can", "--nvm", "--duration", "--record-samples", "--start-delay", "exit status" })
        EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
}

TEST(DtcSimCli, UsageErrorsExitTwo)
{
    EXPECT_EQ(sim("").status, 2);
    EXPECT_EQ(sim("fly").status, 2);
    EXPECT_EQ(sim("run").status, 2);
    TempDir d;
    std::string ok = simtest::source_path("host_sim/scenarios/dol_start.ini");
    EXPECT_EQ(sim("run " + q(ok) + " --bogus").status, 2);
    EXPECT_EQ(sim("run " + q(ok) + " --csv").status, 2);
    EXPECT_EQ(sim("run " + q(ok) + " --controller pid").status, 2);
    auto r = sim("run " + q(ok) + " --can vcan0");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("requires --realtime"), std::string::npos) << r.output;
    r = sim("run " + q(ok) + " --duration inf");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("requires --realtime"), std::string::npos) << r.output;
    r = sim("run " + q(ok) + " --set sim.duration_s");
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.output, "--set sim.duration_s: expected section.key=value (no '=')\n");
    r = sim("run " + q(ok) + " --set sim.nokey=1");
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.output.rfind("--set sim.nokey: unknown key", 0), 0u) << r.output;
    r = sim("run " + q(ok) + " --start-delay -1");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("--start-delay"), std::string::npos) << r.output;
    r = sim("run " + q(ok) + " --csv " + q(d.file("no/such/dir/x.csv")));
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("cannot create"), std::string::npos) << r.output;
}

TEST(DtcSimCli, BadScenarioFilesNameTheLineAndLeaveNothing)
{
    const BadCase cases[] = {
        { "unknown_key", "[sim]\nduration_s = 0.1\n\n[motor]\nRs_ohm = 0.3\nspeed = 3\n", 6, "unknown key 'speed'" },
        { "negative_inertia", "# CASE2 with a typo\n[motor]\nJ_kgm2 = -0.045\n", 3, "J_kgm2 must be > 0" },
        { "malformed", "[load]\nstep = 0.5 8Nm\n", 2, "malformed number '8Nm'" },
        { "nan", "[sim]\nduration_s = nan\n", 2, "malformed number 'nan'" },
        { "out_of_range", "[sim]\nperiod_s = 2e-3\n", 2, "out of range" },
        { "events_order", "[events]\nJ_scale = 2.5 1.4\nB_scale = 2.0 1.4\n", 3, "out of time order" },
        { "unknown_section", "[simulation]\nduration_s = 1\n", 2, "unknown section [simulation]" },
        { "syntax", "[sim]\nduration_s 1\n", 2, "syntax error" },
        // keys of the load models, ramps, faults, inverter and saturation
        { "coulomb", "[load]\ncoulomb_Nm = -2\n", 2, "[load] coulomb_Nm must be >= 0" },
        { "load_ramp", "[load]\nstep = 1 5\nramp = 3 2 8\n", 3, "end time 2 s must be after the start 3 s" },
        { "rs_ramp", "[events]\nRs_ramp = 2 8 1.5\nRs_scale = 4 1\n", 3, "starts inside the ramp on line 2" },
        { "fault_channel", "[faults]\n\nlost = 0.5 phase_a\n", 3, "unknown channel 'phase_a'" },
        { "fault_vdc", "[faults]\nvdc = 0.5 -311\n", 2, "out of range" },
        { "dead_time", "[inverter]\ndead_time_s = -2e-6\n", 2, "[inverter] dead_time_s must be in [0, 5e-05] s" },
        { "saturation", "[motor]\nLm_sat_psi_Wb = 0.7\nLm_sat_exponent = 1.5\n", 3, "Lm_sat_exponent must be in [2, 20]" },
        // implausible plates ([ratings], judged as the drive's CAN write is: ratings_check), named at the field's line
        { "plate_synchronous", kPlate10hp "n_rpm = 1800\n", 10, "[ratings] n_rpm: is not below synchronous speed" },
        { "plate_cos_phi", kPlate10hp "n_rpm = 1744\ncos_phi = 1.2\n", 11, "[ratings] cos_phi: is above its range" },
        { "plate_link", "[ratings]\nP_W = 37285\nV_ll_V = 460\nI_A = 62.8\nf_Hz = 60\nvdc_nom_V = 311\n"
                        "inv_I_rated_A = 78.5\ninv_I_peak_A = 257.6\nn_rpm = 1705\n", 6,
          "[ratings] vdc_nom_V: cannot give the rated line voltage" },
        { "plate_negative", "[ratings]\nP_W = 7457\nV_ll_V = 220\nI_A = -24.4\nf_Hz = 60\nvdc_nom_V = 311\n"
                            "inv_I_rated_A = 30\ninv_I_peak_A = 100\nn_rpm = 1744\n", 4, "[ratings] I_A: must be > 0" },
        { "plate_power_zero", "[ratings]\nP_W = 0\nV_ll_V = 220\nI_A = 24.4\nf_Hz = 60\nvdc_nom_V = 311\n"
                              "inv_I_rated_A = 30\ninv_I_peak_A = 100\nn_rpm = 1744\n", 2, "[ratings] P_W: must be > 0" },
        { "plate_missing", "[ratings]\nP_W = 7457\nV_ll_V = 220\nf_Hz = 60\n", 2, "[ratings] I_A: missing" },
        { "plate_model", "[commission]\nmodel = plate\n", 2, "[commission] model: plate needs a [ratings] section" },
        { "plate_model_name", "[commission]\nmodel = guessed\n", 2, "unknown model 'guessed'" },
        // the control period cannot follow a 200 Hz machine's overspeed (judged by the derivation)
        { "plate_period", "[ratings]\nP_W = 7457\nV_ll_V = 220\nI_A = 24.4\nf_Hz = 200\nvdc_nom_V = 311\n"
                          "inv_I_rated_A = 30\ninv_I_peak_A = 100\nn_rpm = 5850\n", 5,
          "[ratings] f_Hz: is above what the control period follows" },
    };
    TempDir d;
    for (const auto &c : cases) {
        std::string ini = d.file(std::string(c.name) + ".ini");
        simtest::write_file(ini, c.text);
        std::string csv = d.file(std::string(c.name) + ".csv"), json = d.file(std::string(c.name) + ".json");
        auto r = sim("run " + q(ini) + " --csv " + q(csv) + " --metrics " + q(json));
        EXPECT_EQ(r.status, 2) << c.name << ": " << r.output;
        std::string prefix = ini + ":" + std::to_string(c.line) + ": ";
        EXPECT_EQ(r.output.rfind(prefix, 0), 0u) << c.name << ": " << r.output;
        EXPECT_NE(r.output.find(c.what), std::string::npos) << c.name << ": " << r.output;
        EXPECT_EQ(lines(r.output), 1) << c.name << ": " << r.output;
        EXPECT_FALSE(simtest::file_exists(csv)) << c.name;
        EXPECT_FALSE(simtest::file_exists(csv + ".partial")) << c.name;
        EXPECT_FALSE(simtest::file_exists(json)) << c.name;
        EXPECT_FALSE(simtest::file_exists(json + ".partial")) << c.name;
    }
    // A missing file.
    auto r = sim("run " + q(d.file("missing.ini")) + " --csv " + q(d.file("m.csv")));
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.output.rfind(d.file("missing.ini") + ": cannot open", 0), 0u) << r.output;
    EXPECT_FALSE(simtest::file_exists(d.file("m.csv")));
}

TEST(DtcSimCli, FailedRunKeepsAnOlderOutput)
{
    TempDir d;
    simtest::write_file(d.file("bad.ini"), "[motor]\nJ_kgm2 = 0\n");
    simtest::write_file(d.file("old.csv"), "old trace\n");
    auto r = sim("run " + q(d.file("bad.ini")) + " --csv " + q(d.file("old.csv")));
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(simtest::read_file(d.file("old.csv")), "old trace\n");
}

TEST(DtcSimCli, RunWritesTraceAndMetrics)
{
    TempDir d;
    std::string csv = d.file("d.csv"), json = d.file("m.json");
    auto r = sim("run " + q(simtest::source_path("host_sim/scenarios/dol_start.ini")) +
                 " --duration 0.2 --set 'load.step=0.1 5' --csv " + q(csv) + " --metrics " + q(json));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("final"), std::string::npos) << r.output;
    EXPECT_FALSE(simtest::file_exists(csv + ".partial"));
    EXPECT_FALSE(simtest::file_exists(json + ".partial"));

    // CSV: the header names the required columns; 0.2 s at 1 ms = 201 rows, all the same width.
    std::string text = simtest::read_file(csv);
    std::string header = text.substr(0, text.find('\n'));
    for (const char *col : { "t_s", "omega_m_rad_s", "speed_rpm", "te_nm", "ia_a", "ib_a", "ic_a", "vc1_v", "vc2_v",
                             "speed_ref_rpm", "speed_est_rpm", "speed_err_true_rpm", "te_ref_nm", "te_est_nm", "psi_s_wb",
                             "psi_ref_wb", "eps_hat", "eps_true", "w_norm", "zeta_bar", "rs_est_ohm", "vector",
                             "duty0", "faults" })
        EXPECT_NE(("," + header + ",").find("," + std::string(col) + ","), std::string::npos) << col;
    size_t cols = (size_t)std::count(header.begin(), header.end(), ',');
    int rows = 0;
    size_t pos = text.find('\n') + 1;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        std::string row = text.substr(pos, end - pos);
        EXPECT_EQ((size_t)std::count(row.begin(), row.end(), ','), cols) << row;
        ++rows;
        pos = end + 1;
    }
    EXPECT_EQ(rows, 201);

    // JSON parses and carries the run's figures.
    std::string js = simtest::read_file(json);
    cJSON *o = cJSON_Parse(js.c_str());
    ASSERT_NE(o, nullptr) << js;
    const cJSON *sim_s = cJSON_GetObjectItemCaseSensitive(o, "sim_seconds");
    ASSERT_TRUE(cJSON_IsNumber(sim_s));
    EXPECT_NEAR(sim_s->valuedouble, 0.2, 1e-9);
    for (const char *key : { "speed_final_rpm", "speed_final_rad_s", "te_final_nm", "is_rms_final_a", "wall_seconds",
                             "eps_true" })
        EXPECT_TRUE(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(o, key))) << key;
    const cJSON *ctl = cJSON_GetObjectItemCaseSensitive(o, "controller");
    ASSERT_TRUE(cJSON_IsString(ctl));
    EXPECT_STREQ(ctl->valuestring, "none"); // sine supply: no firmware
    // T_L = 5 N m from 0.1 s on, nothing else changes: eps_true = -T_L / J over the last 0.5 s
    // window, which here is the whole 0.2 s run: ticks 0..499 at 0, 500..1000 at -5/0.045.
    const cJSON *eps = cJSON_GetObjectItemCaseSensitive(o, "eps_true");
    EXPECT_NEAR(eps->valuedouble, -5.0 / 0.045 * 500.0 / 1000.0, 0.5);
    cJSON_Delete(o);
}

TEST(DtcSimCli, NvmFileOfTheWrongSizeIsRefusedAndKept)
{
    TempDir d;
    simtest::write_file(d.file("nvm.bin"), "short");
    auto r = sim("run " + q(simtest::source_path("host_sim/scenarios/dol_start.ini")) + " --duration 0.01 --nvm " +
                 q(d.file("nvm.bin")));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("4096-byte"), std::string::npos) << r.output;
    EXPECT_EQ(simtest::read_file(d.file("nvm.bin")), "short");
}

TEST(DtcSimCli, SocketCanUnavailableOrUnknownInterface)
{
    // An interface that exists nowhere: exit 2 either way, and on a kernel
    // without CAN the message says so.
    int fd = socket(PF_CAN, SOCK_RAW, 1 /* CAN_RAW */);
    int err = errno;
    if (fd >= 0)
        close(fd);
    auto r = sim("run " + q(simtest::source_path("host_sim/scenarios/dol_start.ini")) +
                 " --realtime --duration 0.01 --can dtcnone0");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_EQ(lines(r.output), 1) << r.output;
    if (fd < 0 && err == EAFNOSUPPORT)
        EXPECT_NE(r.output.find("SocketCAN is not available in this kernel (errno 97)"), std::string::npos)
            << r.output;
    else
        EXPECT_NE(r.output.find("dtcnone0"), std::string::npos) << r.output;
}

TEST(DtcSimCli, BenchPrintsItsFigure)
{
    // A short inverter-fed file keeps this quick (the default bench file is 5 s).
    TempDir d;
    simtest::write_file(d.file("b.ini"), "[sim]\nduration_s = 0.1\n");
    auto r = sim("bench " + q(d.file("b.ini")));
    ASSERT_EQ(r.status, 0) << r.output;
    std::string last = r.output.substr(r.output.rfind('\n', r.output.size() - 2) + 1);
    // "0.10 s simulated in 0.004 s wall: 25x real time" (std::regex trips a GCC 12 warning under ASan).
    double wall = -1.0;
    unsigned factor = 0;
    char tail[64] = "";
    ASSERT_EQ(std::sscanf(last.c_str(), "0.10 s simulated in %lf s wall: %ux real tim%63s", &wall, &factor, tail), 3)
        << last;
    EXPECT_STREQ(tail, "e");
    EXPECT_GE(wall, 0.0); // printed with three decimals: a short run may show 0.000
    EXPECT_GT(factor, 0u);
    size_t dot = last.find('.', last.find(" in ")); // three decimals of wall time
    EXPECT_EQ(last.substr(dot + 4, 7), " s wall") << last;
    EXPECT_EQ(last.back(), '\n');
}

// --realtime --duration inf runs until SIGINT, then writes its outputs and exits 0.
TEST(DtcSimCli, RealtimeEndsCleanlyOnSigint)
{
    TempDir d;
    std::string json = d.file("rt.json"), csv = d.file("rt.csv");
    std::string ini = simtest::source_path("host_sim/scenarios/dol_start.ini");
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        execl(kSim.c_str(), kSim.c_str(), "run", ini.c_str(), "--realtime", "--duration", "inf", "--quiet",
              "--metrics", json.c_str(), "--csv", csv.c_str(), (char *)nullptr);
        _exit(127);
    }
    struct timespec ts = { 0, 300000000 }; // let it run 0.3 s
    nanosleep(&ts, nullptr);
    ASSERT_EQ(kill(pid, SIGINT), 0);
    int st = 0;
    ASSERT_EQ(waitpid(pid, &st, 0), pid);
    ASSERT_TRUE(WIFEXITED(st));
    EXPECT_EQ(WEXITSTATUS(st), 0);
    std::string js = simtest::read_file(json);
    cJSON *o = cJSON_Parse(js.c_str());
    ASSERT_NE(o, nullptr) << js;
    const cJSON *sim_s = cJSON_GetObjectItemCaseSensitive(o, "sim_seconds");
    ASSERT_TRUE(cJSON_IsNumber(sim_s));
    EXPECT_GT(sim_s->valuedouble, 0.0);
    EXPECT_LT(sim_s->valuedouble, 60.0); // paced, not free-running for minutes
    cJSON_Delete(o);
    EXPECT_TRUE(simtest::file_exists(csv));
    EXPECT_FALSE(simtest::file_exists(csv + ".partial"));
}

// Hostile inputs: a scenario that is not a regular file, too large or with a
// NUL byte is refused at once (no hang, exit 2, one line); an output that is
// a device, a FIFO or the scenario itself is refused and left untouched.
TEST(DtcSimCli, ScenarioMustBeARegularTextFileOfBoundedSize)
{
    TempDir dir;
    const std::string fifo = dir.file("fifo.ini");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    for (const std::string &path : { fifo, std::string("/dev/zero"), dir.path() }) {
        auto r = simtest::run_command("timeout 10 " + kSim + " run " + q(path));
        EXPECT_EQ(r.status, 2) << path << ": " << r.output;
        EXPECT_NE(r.output.find(path + ": not a regular file"), std::string::npos) << r.output;
        EXPECT_EQ(lines(r.output), 1) << r.output;
    }
    const std::string big = dir.file("big.ini");
    simtest::write_file(big, "[sim]\nduration_s = 0.01\n" + std::string(1100000, '#') + "\n");
    auto r = sim("run " + q(big));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("larger than 1048576 bytes"), std::string::npos) << r.output;
    const std::string nul = dir.file("nul.ini");
    simtest::write_file(nul, std::string("[sim]\nduration_s = 1\0junk\n", 26));
    r = sim("run " + q(nul));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(nul + ":2: NUL byte"), std::string::npos) << r.output;
}

TEST(DtcSimCli, OutputsAreNewOrRegularFilesNeverTheInputOrADevice)
{
    TempDir dir;
    const std::string sc = dir.file("s.ini");
    const std::string text = "[sim]\nduration_s = 0.01\n";
    simtest::write_file(sc, text);
    const std::string fifo = dir.file("out.fifo");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    struct Case {
        std::string args, what;
    };
    const Case cases[] = {
        { "--csv " + q(sc), "--csv " + sc + ": is the scenario file itself" },
        { "--metrics " + q(sc), "--metrics " + sc + ": is the scenario file itself" },
        { "--csv /dev/null", "--csv /dev/null: not a regular file" },
        { "--metrics " + q(fifo), "--metrics " + fifo + ": not a regular file" },
        { "--csv " + q(dir.path()), "not a regular file" },
        { "--nvm " + q(sc), "--nvm " + sc + ": is the scenario file itself" },
    };
    for (const Case &c : cases) {
        auto r = simtest::run_command("timeout 10 " + kSim + " run " + q(sc) + " " + c.args);
        EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
        EXPECT_NE(r.output.find(c.what), std::string::npos) << r.output;
    }
    EXPECT_EQ(simtest::read_file(sc), text) << "the scenario is untouched";
    struct stat st;
    ASSERT_EQ(stat(fifo.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO is still a FIFO";
    // A new path and an existing regular file are fine.
    const std::string old = dir.file("old.json");
    simtest::write_file(old, "old");
    auto r = sim("run " + q(sc) + " --csv " + q(dir.file("new.csv")) + " --metrics " + q(old) + " --quiet");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(simtest::read_file(old), "old");
}

// A scenario's [control] values go through the firmware's ctl_cfg_check, with
// the refusal a CAN write gets (0x06040043): the key that makes the
// configuration inconsistent is named with its line, nothing runs.
TEST(DtcSimCli, InconsistentControlValuesAreRefusedLikeACanWrite)
{
    TempDir dir;
    const std::string sc = dir.file("v.ini");
    simtest::write_file(sc, "[sim]\nduration_s = 0.05\n[control]\nvdc_max_V = 400\nvdc_min_V = 500\n");
    const std::string m = dir.file("m.json");
    auto r = sim("run " + q(sc) + " --metrics " + q(m));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(sc + ":5: [control] vdc_min_V = 500 refused by the firmware"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("0x06040043"), std::string::npos) << r.output;
    EXPECT_EQ(lines(r.output), 1) << r.output;
    EXPECT_FALSE(simtest::file_exists(m));
    r = sim("run " + q(sc) + " --set control.vdc_min_V=300 --quiet");
    EXPECT_EQ(r.status, 0) << "the --set value replaces the file's: " << r.output;
}

// dtc-sim never removes or truncates a file it did not create: a scenario
// that happens to be named like an output's temporary (run.partial for
// --csv run) is refused before anything is opened, and stays byte for byte,
// also when the run would have failed anyway (a --metrics in a missing folder).
TEST(DtcSimCli, AScenarioNamedLikeATemporaryIsNeverTouched)
{
    TempDir d;
    const std::string sc = d.file("run.partial");
    const std::string text = "[sim]\nduration_s = 0.01\n# keep me\n";
    simtest::write_file(sc, text);
    struct Case {
        std::string args, what;
    };
    const Case cases[] = {
        { "--csv " + q(d.file("run")), "--csv " + d.file("run") + ": its temporary file " + sc +
                                           " is the scenario file itself" },
        { "--csv " + q(d.file("run")) + " --metrics " + q(d.file("missing/m.json")),
          "--metrics " + d.file("missing/m.json") + ": cannot create" },
        { "--metrics " + q(d.file("run")), "is the scenario file itself" },
        { "--record-samples " + q(d.file("run")), "is the scenario file itself" },
        { "--csv " + q(d.file("./run")), "is the scenario file itself" },
    };
    for (const Case &c : cases) {
        auto r = sim("run " + q(sc) + " --quiet " + c.args);
        EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
        EXPECT_NE(r.output.find(c.what), std::string::npos) << r.output;
        EXPECT_EQ(lines(r.output), 1) << r.output;
        EXPECT_EQ(simtest::read_file(sc), text) << c.args;
        EXPECT_FALSE(simtest::file_exists(d.file("run"))) << c.args;
    }
    // Another name of the same file (a hard link) is caught by its inode.
    ASSERT_EQ(link(sc.c_str(), d.file("h.partial").c_str()), 0);
    auto r = sim("run " + q(sc) + " --quiet --nvm " + q(d.file("h.partial")));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("is the scenario file itself"), std::string::npos) << r.output;
    r = sim("run " + q(sc) + " --quiet --csv " + q(d.file("h")));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("its temporary file " + d.file("h.partial") + " is the scenario file itself"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(simtest::read_file(sc), text);
}

// Two outputs that name one file, or an output that is another's temporary,
// are refused (exit 2) before any file is created or changed.
TEST(DtcSimCli, OutputsThatNameOneFileAreRefusedBeforeAnythingIsTouched)
{
    TempDir d;
    const std::string sc = d.file("s.ini");
    simtest::write_file(sc, "[sim]\nduration_s = 0.01\n");
    const std::string a = d.file("A"), x = d.file("X");
    struct Case {
        std::string args, what;
    };
    const Case cases[] = {
        { "--csv " + q(a) + " --metrics " + q(d.file("./A")), "--metrics " + d.file("./A") +
                                                                  ": is the same file as --csv " + a },
        { "--csv " + q(x) + " --metrics " + q(x + ".partial"), "--metrics " + x + ".partial: is the temporary file "
                                                                   "of --csv " + x },
        { "--metrics " + q(x + ".partial") + " --csv " + q(x), "is the temporary file of --csv " + x },
        { "--csv " + q(a) + " --record-samples " + q(d.file("sub/../A")), "is the same file as --csv " + a },
        { "--nvm " + q(a) + " --csv " + q(a + ".tmp"), "--csv " + a + ".tmp: is the temporary file of --nvm " + a },
        { "--nvm " + q(x) + " --metrics " + q(x), "is the same file as --metrics " + x },
    };
    ASSERT_EQ(mkdir(d.file("sub").c_str(), 0700), 0);
    for (const Case &c : cases) {
        auto r = sim("run " + q(sc) + " --quiet " + c.args);
        EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
        EXPECT_NE(r.output.find(c.what), std::string::npos) << r.output;
        EXPECT_EQ(lines(r.output), 1) << r.output;
        for (const std::string &f : { a, a + ".partial", a + ".tmp", x, x + ".partial", x + ".tmp" })
            EXPECT_FALSE(simtest::file_exists(f)) << c.args << ": " << f << " was created";
    }
    // The same with existing outputs: refused, and both kept as they were.
    simtest::write_file(a, "old A");
    simtest::write_file(x, "old X");
    for (const std::string &args : { "--csv " + q(a) + " --metrics " + q(d.file("./A")),
                                     "--csv " + q(x) + " --nvm " + q(d.file("sub/../X")) }) {
        auto r = sim("run " + q(sc) + " --quiet " + args);
        EXPECT_EQ(r.status, 2) << args << ": " << r.output;
        EXPECT_NE(r.output.find("is the same file as"), std::string::npos) << r.output;
    }
    EXPECT_EQ(simtest::read_file(a), "old A");
    EXPECT_EQ(simtest::read_file(x), "old X");
    // A temporary left by an interrupted run is not ours to truncate: refused, kept.
    simtest::write_file(x + ".partial", "someone's file");
    auto r = sim("run " + q(sc) + " --quiet --csv " + q(x));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--csv " + x + ": its temporary file " + x + ".partial exists"), std::string::npos)
        << r.output;
    EXPECT_EQ(simtest::read_file(x + ".partial"), "someone's file");
    EXPECT_EQ(simtest::read_file(x), "old X");
    // Distinct outputs are fine, and replace the old ones.
    ASSERT_EQ(std::remove((x + ".partial").c_str()), 0);
    r = sim("run " + q(sc) + " --quiet --csv " + q(a) + " --metrics " + q(x));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(simtest::read_file(a), "old A");
    EXPECT_NE(simtest::read_file(x), "old X");
}

// Arguments that do not fit are refused with a message, never cut short into
// something that runs; numbers are decimal only.
TEST(DtcSimCli, OverLongArgumentsAndNonDecimalNumbersAreRefused)
{
    const std::string ok = q(simtest::source_path("host_sim/scenarios/dol_start.ini"));
    struct Case {
        std::string args, what;
    };
    const Case cases[] = {
        { "--duration 0.05" + std::string(44, '0') + "junk", "--duration: '0.05" + std::string(36, '0') +
                                                                 "...' is longer than 48 characters" },
        { "--duration 0.05" + std::string(50, '0'), "is longer than 48 characters" },
        { "--duration 0x10", "--duration: '0x10' is not a decimal number of seconds" },
        { "--duration 0x1p-4", "--duration: '0x1p-4' is not a decimal number" },
        { "--duration nan", "not a decimal number" },
        { "--start-delay 0x10", "--start-delay: '0x10' is not a time in 0..600 s" },
        { "--start-delay inf", "--start-delay: 'inf' is not a time" },
        { "--set sim.duration_s=0x10", "--set sim.duration_s: [sim] duration_s: malformed number '0x10'" },
        { "--set 'sim.duration_s" + std::string(120, ' ') + "junk=0.05'", "the key is longer than 127 characters" },
        { "--set control." + std::string(120, 'k') + "=1", "the key is longer than 127 characters" },
        { "--set sim.duration_s=0.05" + std::string(252, '0'), "value longer than 255 characters" },
    };
    for (const Case &c : cases) {
        auto r = sim("run " + ok + " --quiet " + c.args);
        EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
        EXPECT_NE(r.output.find(c.what), std::string::npos) << c.args << ": " << r.output;
        EXPECT_EQ(lines(r.output), 1) << r.output;
    }
    // Within the limits the same spellings run: 48 characters of --duration, a decimal --start-delay.
    auto r = sim("run " + ok + " --quiet --duration 0.05" + std::string(44, '0') + " --start-delay 1e-2");
    EXPECT_EQ(r.status, 0) << r.output;
}
