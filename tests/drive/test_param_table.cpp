// The generated object dictionary against its source, tools/params/parameters.toml
// (read here with Python's tomllib, not with the generator), the firmware
// defaults (ctl_cfg_default) against the table, the EDS against the C table,
// and the checked-in docs/parameters.md against the generated one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "co_test_util.hpp"

extern "C" {
#include "dtc/ctl.h"
}

namespace {

struct TomlEntry {
    std::string name, type, access, bind, min, max, def;
    int index = 0, sub = 0;
    bool persist = false, runtime = false, pdo = false;
    double scale = 1.0, resolution = 1.0;
};

// Expands the table the simple way (count -> name_1.., sub + i, list defaults)
// and prints one tab-separated line per entry, plus the PDO lists.
const char *kDumpScript = R"PY(
import sys, tomllib
t = tomllib.load(open(sys.argv[1], 'rb'))
for e in t['param']:
    n = e.get('count', 1)
    d = e.get('default')
    for i in range(n):
        name = e['name'] if n == 1 else f"{e['name']}_{i + 1}"
        dv = d[i] if isinstance(d, list) else d
        print('P', name, e['index'], e.get('sub', 0) + i, e['type'], e['access'],
              int(e.get('persist', False)), int(e.get('runtime', False)), int(e.get('pdo', False)),
              repr(e.get('min')), repr(e.get('max')), repr(dv).replace('\t', ' '),
              e['bind'].replace('{i}', str(i)), repr(float(e.get('scale', 1.0))),
              repr(float(e.get('resolution', 1.0))), sep='\t')
for kind in ('tpdo', 'rpdo'):
    for p in t.get(kind, []):
        print('M', kind, p['num'], *p['signals'], sep='\t')
)PY";

std::vector<std::string> split_tabs(const std::string &line)
{
    std::vector<std::string> out;
    std::string cur;
    for (char c : line) {
        if (c == '\t') {
            out.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

struct Toml {
    std::vector<TomlEntry> params;
    std::vector<std::vector<std::string>> maps; // kind, num, signals...
};

Toml read_toml()
{
    Toml t;
    // One script per process: ctest runs each test of this suite in its own
    // process, in parallel, and a shared file could be truncated under a reader.
    std::string script = std::string(DTC_BINARY_DIR) + "/test_param_table_dump." + std::to_string(getpid()) + ".py";
    {
        std::ofstream f(script);
        f << kDumpScript;
    }
    std::string cmd = "python3 " + script + " " + DTC_SOURCE_DIR + "/tools/params/parameters.toml";
    FILE *p = popen(cmd.c_str(), "r");
    if (p == nullptr)
        return t;
    char buf[4096];
    while (fgets(buf, sizeof buf, p) != nullptr) {
        std::string line(buf);
        while (!line.empty() && (line.back() == '\n' || line.back() == '\r'))
            line.pop_back();
        auto f = split_tabs(line);
        if (f[0] == "P" && f.size() == 15) {
            TomlEntry e;
            e.name = f[1];
            e.index = std::stoi(f[2]);
            e.sub = std::stoi(f[3]);
            e.type = f[4];
            e.access = f[5];
            e.persist = f[6] == "1";
            e.runtime = f[7] == "1";
            e.pdo = f[8] == "1";
            e.min = f[9];
            e.max = f[10];
            e.def = f[11];
            e.bind = f[12];
            e.scale = std::stod(f[13]);
            e.resolution = std::stod(f[14]);
            t.params.push_back(e);
        } else if (f[0] == "M") {
            t.maps.emplace_back(f.begin() + 1, f.end());
        }
    }
    pclose(p);
    std::remove(script.c_str());
    return t;
}

// The CiA 301 data type codes, written out independently of the generator.
const std::map<std::string, int> kTypeCode = {
    {"BOOLEAN", 1},    {"INTEGER8", 2},   {"INTEGER16", 3},      {"INTEGER32", 4}, {"UNSIGNED8", 5},
    {"UNSIGNED16", 6}, {"UNSIGNED32", 7}, {"REAL32", 8},         {"VISIBLE_STRING", 9}, {"DOMAIN", 15}};
const std::map<std::string, int> kTypeBits = {{"INTEGER8", 8}, {"INTEGER16", 16}, {"INTEGER32", 32}, {"UNSIGNED8", 8},
                                              {"UNSIGNED16", 16}, {"UNSIGNED32", 32}, {"REAL32", 32}};

// Compare a raw table value with the TOML number (a Python repr).
void expect_num(const co_param *p, const co_num &v, const std::string &toml, const char *what)
{
    SCOPED_TRACE(std::string(p->name) + " " + what + " = " + toml);
    if (p->dtype == CO_DT_REAL32) {
        EXPECT_EQ(v.f, static_cast<float>(std::stod(toml)));
    } else if (p->dtype == CO_DT_INTEGER8 || p->dtype == CO_DT_INTEGER16 || p->dtype == CO_DT_INTEGER32) {
        EXPECT_EQ(v.i, std::stoll(toml));
    } else {
        EXPECT_EQ(v.u, static_cast<uint32_t>(std::stoull(toml)));
    }
}

class ParamTable : public ::testing::Test {
protected:
    static void SetUpTestSuite() { toml = new Toml(read_toml()); }
    static void TearDownTestSuite()
    {
        delete toml;
        toml = nullptr;
    }
    // Every test reads the table; an empty read must fail them all, not let
    // their loops pass over nothing.
    void SetUp() override { ASSERT_GT(toml->params.size(), 100u) << "python3 with tomllib must be on PATH"; }
    static Toml *toml;
};
Toml *ParamTable::toml = nullptr;

TEST_F(ParamTable, TomlWasRead)
{
    ASSERT_GT(toml->params.size(), 100u) << "python3 with tomllib must be on PATH";
}

TEST_F(ParamTable, GeneratedCTableEqualsToml)
{
    std::set<std::string> seen;
    for (const TomlEntry &e : toml->params) {
        SCOPED_TRACE(e.name);
        const co_param *p = co_od_find_name(&drive_od, e.name.c_str());
        ASSERT_NE(p, nullptr);
        seen.insert(e.name);
        EXPECT_EQ(p->index, e.index);
        EXPECT_EQ(p->sub, e.sub);
        EXPECT_EQ(p->dtype, kTypeCode.at(e.type));
        EXPECT_EQ((p->flags & CO_F_WRITE) != 0, e.access == "rw");
        EXPECT_NE(p->flags & CO_F_READ, 0);
        EXPECT_EQ((p->flags & CO_F_PERSIST) != 0, e.persist);
        EXPECT_EQ((p->flags & CO_F_RUNTIME) != 0, e.runtime);
        EXPECT_EQ((p->flags & CO_F_PDO) != 0, e.pdo);
        if (e.type == "VISIBLE_STRING" || e.type == "DOMAIN") {
            if (e.def != "None") {
                ASSERT_NE(p->str, nullptr);
                EXPECT_EQ("'" + std::string(p->str) + "'", e.def);
            }
            continue;
        }
        EXPECT_EQ((p->flags & CO_F_LIMITS) != 0, e.min != "None");
        if (e.min != "None") {
            expect_num(p, p->min, e.min, "min");
            expect_num(p, p->max, e.max, "max");
        }
        if (e.name == "dictionary_signature")
            EXPECT_NE(p->def.u, 0u); // the table holds a placeholder; the generator computes the CRC
        else
            expect_num(p, p->def, e.def, "default");
        // raw = internal * scale / resolution
        EXPECT_FLOAT_EQ(p->k, static_cast<float>(e.scale / e.resolution));
    }
    // Everything else in the C table is generated: PDO communication and
    // mapping objects and subindex 0 of the records.
    for (uint32_t i = 0; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        if (seen.count(p->name))
            continue;
        bool pdo_obj = (p->index >= 0x1400 && p->index <= 0x1403) || (p->index >= 0x1600 && p->index <= 0x1603) ||
                       (p->index >= 0x1800 && p->index <= 0x1803) || (p->index >= 0x1A00 && p->index <= 0x1A03);
        EXPECT_TRUE(pdo_obj || p->sub == 0) << p->name << " is neither in the TOML nor generated";
        EXPECT_EQ(p->flags & CO_F_WRITE, 0) << p->name;
    }
}

TEST_F(ParamTable, SortedUniqueAndFindable)
{
    std::set<std::string> names;
    for (uint32_t i = 0; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        EXPECT_TRUE(names.insert(p->name).second) << "duplicate " << p->name;
        if (i > 0) {
            uint32_t a = (uint32_t(co_params[i - 1].index) << 8) | co_params[i - 1].sub;
            uint32_t b = (uint32_t(p->index) << 8) | p->sub;
            EXPECT_LT(a, b) << p->name;
        }
        uint32_t abort = 1;
        EXPECT_EQ(co_od_find(&drive_od, p->index, p->sub, &abort), p);
        EXPECT_EQ(abort, 0u);
    }
    uint32_t abort = 0;
    EXPECT_EQ(co_od_find(&drive_od, 0x2FFF, 0, &abort), nullptr);
    EXPECT_EQ(abort, cotest::kAbortNoObject);
    EXPECT_EQ(co_od_find(&drive_od, 0x2000, 0x7F, &abort), nullptr);
    EXPECT_EQ(abort, cotest::kAbortNoSub);
    EXPECT_EQ(co_od_find(&drive_od, 0x1000, 1, &abort), nullptr);
    EXPECT_EQ(abort, cotest::kAbortNoSub);
}

TEST_F(ParamTable, PdoMappingsEqualTomlLists)
{
    for (const auto &m : toml->maps) {
        const std::string &kind = m[0];
        int num = std::stoi(m[1]);
        SCOPED_TRACE(kind + " " + m[1]);
        uint16_t map_index = uint16_t((kind == "tpdo" ? 0x1A00 : 0x1600) + num - 1);
        uint16_t comm_index = uint16_t((kind == "tpdo" ? 0x1800 : 0x1400) + num - 1);
        const co_param *n = co_od_find(&drive_od, map_index, 0, nullptr);
        ASSERT_NE(n, nullptr);
        EXPECT_EQ(n->def.u, m.size() - 2);
        int bits = 0;
        for (size_t j = 2; j < m.size(); j++) {
            const TomlEntry *sig = nullptr;
            for (const auto &e : toml->params)
                if (e.name == m[j])
                    sig = &e;
            ASSERT_NE(sig, nullptr) << m[j];
            const co_param *w = co_od_find(&drive_od, map_index, uint8_t(j - 1), nullptr);
            ASSERT_NE(w, nullptr);
            uint32_t expect = (uint32_t(sig->index) << 16) | (uint32_t(sig->sub) << 8) | uint32_t(kTypeBits.at(sig->type));
            EXPECT_EQ(w->def.u, expect) << m[j];
            bits += kTypeBits.at(sig->type);
        }
        EXPECT_LE(bits, 64);
        const co_param *cob = co_od_find(&drive_od, comm_index, 1, nullptr);
        ASSERT_NE(cob, nullptr);
        uint32_t base = (kind == "tpdo" ? 0x180u : 0x200u) + 0x100u * uint32_t(num - 1);
        EXPECT_EQ(cob->def.u & 0x7FFu, base);
        EXPECT_EQ(cob->bind, CO_BIND_NODEID);
    }
}

// The firmware's defaults (owned by the control code) must be the table's.
TEST_F(ParamTable, DefaultsEqualCtlCfgDefault)
{
    ctl_cfg cfg;
    std::memset(&cfg, 0, sizeof cfg);
    ctl_cfg_default(&cfg);
    int checked = 0;
    for (const TomlEntry &e : toml->params) {
        if (e.bind.rfind("cfg.", 0) != 0)
            continue;
        SCOPED_TRACE(e.name + " (" + e.bind + ")");
        const co_param *p = co_od_find_name(&drive_od, e.name.c_str());
        ASSERT_NE(p, nullptr);
        const uint8_t *field = reinterpret_cast<const uint8_t *>(&cfg) + p->offset;
        double fw;
        if (p->ckind == CO_CK_FLOAT) {
            float f;
            std::memcpy(&f, field, 4);
            fw = f;
        } else if (p->ckind == CO_CK_BOOL) {
            fw = field[0] ? 1.0 : 0.0;
        } else {
            uint32_t u = 0;
            std::memcpy(&u, field, p->csize);
            fw = u;
        }
        double table = std::stod(e.def) / (e.scale / e.resolution);
        EXPECT_NEAR(fw, table, 1e-6 * std::max(1.0, std::fabs(table)))
            << "firmware default " << fw << ", table default " << e.def;
        checked++;
    }
    EXPECT_GT(checked, 50);
}

// A few bindings spelled out by hand, so a wrong offset cannot hide behind
// the generator's own offsetof.
TEST_F(ParamTable, BindingsPointAtTheNamedFields)
{
    EXPECT_EQ(co_od_find_name(&drive_od, "rbfn_k")->offset, offsetof(ctl_cfg, speed.rbfn.k));
    EXPECT_EQ(co_od_find_name(&drive_od, "rbfn_gamma_w")->offset, offsetof(ctl_cfg, speed.rbfn.gamma_w));
    EXPECT_EQ(co_od_find_name(&drive_od, "rbfn_centre_3")->offset, offsetof(ctl_cfg, speed.rbfn.centre) + 2 * sizeof(float));
    EXPECT_EQ(co_od_find_name(&drive_od, "rbfn_width_9")->offset, offsetof(ctl_cfg, speed.rbfn.width) + 8 * sizeof(float));
    EXPECT_EQ(co_od_find_name(&drive_od, "ip_wn_rad_s")->offset, offsetof(ctl_cfg, speed.ip.wn_rad_s));
    EXPECT_EQ(co_od_find_name(&drive_od, "psi_ref_Wb")->offset, offsetof(ctl_cfg, dtc.psi_ref_Wb));
    EXPECT_EQ(co_od_find_name(&drive_od, "te_max_Nm")->offset, offsetof(ctl_cfg, speed.te_max_Nm));
    EXPECT_EQ(co_od_find_name(&drive_od, "i_trip_A")->offset, offsetof(ctl_cfg, i_trip_A));
    EXPECT_EQ(co_od_find_name(&drive_od, "tel_speed_est_rpm")->offset, offsetof(drive_snapshot, tel.omega_est_rad_s));
    EXPECT_EQ(co_od_find_name(&drive_od, "tel_vdc_diff_V")->offset, offsetof(drive_snapshot, vdc_diff_V));
    EXPECT_EQ(co_od_find_name(&drive_od, "telemetry_hz")->offset, offsetof(co_comm_cfg, telemetry_hz));
}

// Eq. 3 of the paper with K_T = 1, from the table's own defaults.
TEST_F(ParamTable, DerivedIpGainDefaultsFollowEquation3)
{
    auto def = [&](const char *n) {
        for (const auto &e : toml->params)
            if (e.name == n)
                return std::stod(e.def);
        ADD_FAILURE() << n;
        return 0.0;
    };
    double wn = def("ip_wn_rad_s"), zeta = def("ip_zeta"), j = def("motor_J_kgm2"), b = def("motor_B_Nms");
    EXPECT_NEAR(def("ip_ki"), wn * wn * j, 1e-5);
    EXPECT_NEAR(def("ip_kp"), 2.0 * zeta * wn * j - b, 1e-5);
}

// After drive_init on an erased NVM every writable entry reads its table default.
TEST_F(ParamTable, FreshDriveReadsTableDefaults)
{
    cotest::Bench b;
    for (const TomlEntry &e : toml->params) {
        if (e.access != "rw")
            continue;
        SCOPED_TRACE(e.name);
        const co_param *p = co_od_find_name(&drive_od, e.name.c_str());
        ASSERT_NE(p, nullptr);
        if (p->bind == DRIVE_BIND_FN && (p->index == 0x1010 || p->index == 0x1011 || p->index == 0x6040 ||
                                      p->name == std::string("scope_command")))
            continue; // commands, not values
        co_num v;
        v.u = 0;
        ASSERT_EQ(co_od_read_num(&b.d->co, p, &v), 0u);
        if (p->dtype == CO_DT_REAL32)
            EXPECT_NEAR(v.f, std::stod(e.def), 1e-6 * std::max(1.0, std::fabs(std::stod(e.def))));
        else
            expect_num(p, v, e.def, "value after init");
    }
}

std::string slurp(const std::string &path)
{
    std::ifstream f(path, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

TEST(ParamDocs, CheckedInCopyEqualsGenerated)
{
    std::string gen = slurp(std::string(DTC_BINARY_DIR) + "/docs/parameters.md");
    std::string repo = slurp(std::string(DTC_SOURCE_DIR) + "/docs/parameters.md");
    ASSERT_FALSE(gen.empty()) << "the build did not generate docs/parameters.md";
    EXPECT_TRUE(gen == repo) << "docs/parameters.md is out of date; regenerate it:\n  python3 tools/params/gen_params.py "
                                "--table tools/params/parameters.toml --md docs/parameters.md";
}

// The generator refuses an inconsistent table with one clear line and exit
// status 2, and writes no output.
TEST(ParamGenerator, RefusesBadTablesWithAClearMessage)
{
    std::string dir = std::string(DTC_BINARY_DIR) + "/test_param_gen";
    std::string gen = std::string(DTC_SOURCE_DIR) + "/tools/params/gen_params.py";
    ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
    const std::string dev = "[device]\nvendor_name = \"v\"\nvendor_id = 0\nproduct_name = \"p\"\n"
                            "product_code = 1\nrevision = 1\nserial = 1\ndevice_type = 0\nsw_version = \"1\"\n"
                            "default_node_id = 1\ntick_hz = 5000\nscope_samples = 1024\nscope_channels = 4\n";
    auto param = [](const std::string &name, const std::string &extra) {
        return "[[param]]\nname = \"" + name + "\"\nindex = 0x2000\ntype = \"REAL32\"\naccess = \"rw\"\n"
               "bind = \"cfg.speed.te_max_Nm\"\ndescription = \"d\"\n" + extra;
    };
    struct Case {
        std::string toml, expect;
    } cases[] = {
        {dev + param("a", "min = 0.0\nmax = 1.0\ndefault = 2.0\n"), "a: default 2.0 outside [0.0, 1.0]"},
        {dev + param("a", "default = 1.0\nmin = 0.0\nmax = 5.0\n") + param("b", "default = 1.0\n"),
         "b: 0x2000:0 already used by a"},
        {dev + param("a", "default = 1.0\nbind = \"cfg.x\"\n"), "not valid TOML"},
        {dev + param("a", "defualt = 1.0\n"), "a: unknown key 'defualt'"},
        {dev + "[[param]]\nname = \"a\"\nindex = 0x2000\ntype = \"FLOAT99\"\naccess = \"rw\"\n"
               "bind = \"cfg.speed.te_max_Nm\"\ndescription = \"d\"\ndefault = 1.0\n",
         "a: unknown type 'FLOAT99'"},
        {"[device]\n", "[device]: missing"},
        {dev + param("a", "default = 1.0\n") + "[[tpdo]]\nnum = 1\nsignals = [\"zz\"]\n",
         "[[tpdo]] 1: unknown signal 'zz'"},
    };
    int i = 0;
    for (const Case &c : cases) {
        SCOPED_TRACE(c.expect);
        std::string table = dir + "/t" + std::to_string(i) + ".toml";
        std::string out = dir + "/out" + std::to_string(i) + ".h";
        std::string err = dir + "/err" + std::to_string(i);
        {
            std::ofstream f(table);
            f << c.toml;
        }
        int rc = std::system(("python3 " + gen + " --table " + table + " --c-header " + out + " 2> " + err).c_str());
        ASSERT_TRUE(WIFEXITED(rc));
        EXPECT_EQ(WEXITSTATUS(rc), 2);
        std::string msg = slurp(err);
        EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
        EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 1) << msg;
        EXPECT_FALSE(std::ifstream(out).good()) << "an output was written";
        i++;
    }
}

// CiA 306 [FileInfo] dates: CreationDate/ModificationDate as
// mm-dd-yyyy, CreationTime/ModificationTime as hh:mm with AM or PM, the modification not
// before the creation.
TEST(ParamEds, FileInfoHasCreationAndModificationDates)
{
    std::ifstream f(std::string(DTC_BINARY_DIR) + "/drive.eds");
    ASSERT_TRUE(f.good());
    std::map<std::string, std::string> info;
    std::string line, sec;
    while (std::getline(f, line)) {
        if (!line.empty() && line[0] == '[') {
            sec = line;
            continue;
        }
        auto eq = line.find('=');
        if (sec == "[FileInfo]" && eq != std::string::npos)
            info[line.substr(0, eq)] = line.substr(eq + 1);
    }
    // (no std::regex: GCC 12 warns about its std::function with -O2 and the sanitizers)
    auto num = [](const std::string &v, size_t at, int lo, int hi) {
        if (v.size() < at + 2 || !std::isdigit(uint8_t(v[at])) || !std::isdigit(uint8_t(v[at + 1])))
            return false;
        int n = (v[at] - '0') * 10 + (v[at + 1] - '0');
        return n >= lo && n <= hi;
    };
    auto is_date = [&](const std::string &v) { // mm-dd-yyyy
        return v.size() == 10 && num(v, 0, 1, 12) && v[2] == '-' && num(v, 3, 1, 31) && v[5] == '-' &&
               num(v, 6, 20, 20) && num(v, 8, 0, 99);
    };
    auto is_time = [&](const std::string &v) { // hh:mmAM or hh:mmPM
        return v.size() == 7 && num(v, 0, 1, 12) && v[2] == ':' && num(v, 3, 0, 59) &&
               (v.compare(5, 2, "AM") == 0 || v.compare(5, 2, "PM") == 0);
    };
    for (const char *k : {"CreationDate", "ModificationDate"})
        EXPECT_TRUE(is_date(info[k])) << k << "=" << info[k];
    for (const char *k : {"CreationTime", "ModificationTime"})
        EXPECT_TRUE(is_time(info[k])) << k << "=" << info[k];
    auto ymd = [](const std::string &d) { return d.substr(6, 4) + d.substr(0, 2) + d.substr(3, 2); };
    EXPECT_LE(ymd(info["CreationDate"]), ymd(info["ModificationDate"]));
    EXPECT_FALSE(info["CreatedBy"].empty());
}

// The EDS (what PC tools load) lists exactly the objects the firmware serves.
TEST(ParamEds, ObjectsEqualTheCTable)
{
    std::ifstream f(std::string(DTC_BINARY_DIR) + "/drive.eds");
    ASSERT_TRUE(f.good());
    std::set<std::pair<int, int>> eds;
    std::map<std::pair<int, int>, int> dtype;
    std::set<int> records;
    std::string line;
    std::pair<int, int> cur{-1, -1};
    while (std::getline(f, line)) {
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (line.size() > 2 && line[0] == '[') {
            std::string sec = line.substr(1, line.size() - 2);
            cur = {-1, -1};
            if (sec.size() >= 4 && std::isxdigit(uint8_t(sec[0])) && std::isxdigit(uint8_t(sec[3]))) {
                int index = std::stoi(sec.substr(0, 4), nullptr, 16);
                if (sec.size() == 4)
                    cur = {index, 0};
                else if (sec.compare(4, 3, "sub") == 0)
                    cur = {index, std::stoi(sec.substr(7), nullptr, 16)};
            }
        } else if (cur.first >= 0 && line.rfind("ObjectType=", 0) == 0) {
            int ot = std::stoi(line.substr(11), nullptr, 16);
            if (ot == 7)
                eds.insert(cur);
            else
                records.insert(cur.first);
        } else if (cur.first >= 0 && line.rfind("DataType=", 0) == 0) {
            dtype[cur] = std::stoi(line.substr(9), nullptr, 16);
        }
    }
    std::set<std::pair<int, int>> c;
    for (uint32_t i = 0; i < CO_PARAM_COUNT; i++)
        c.insert({co_params[i].index, co_params[i].sub});
    EXPECT_EQ(eds, c);
    for (const auto &k : c) {
        const co_param *p = co_od_find(&drive_od, uint16_t(k.first), uint8_t(k.second), nullptr);
        EXPECT_EQ(dtype[k], p->dtype) << std::hex << k.first << ":" << k.second;
    }
}

} // namespace
