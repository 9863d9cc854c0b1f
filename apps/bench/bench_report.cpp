#include "bench_report.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>

#include "core/parallel.h"
#include "plot_script.h"

namespace penumbra::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kAccelNames[] = {"embree", "raw_embree", "naive"};

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// Three significant digits, without exponent for the usual range.
std::string rate(double v) {
    if (!(v > 0.0)) return "-";
    if (v >= 100.0) return fmt("%.0f", v);
    if (v >= 10.0) return fmt("%.1f", v);
    if (v >= 1.0) return fmt("%.2f", v);
    return fmt("%.3g", v);
}

std::optional<double> ratio1(double a, double b) {
    if (!(a > 0.0) || !(b > 0.0)) return std::nullopt;
    return a / b;
}

std::string opt(const std::optional<double>& v, const char* f = "%.2f") { return v ? fmt(f, *v) : "-"; }

std::string times(const std::optional<double>& v) {
    if (!v) return "-";
    return (*v >= 100.0 ? fmt("%.0f", *v) : fmt("%.1f", *v)) + "x";
}

// Accelerators: 0 embree, 1 raw, 2 naive, 3 raw without the robust flag,
// 4 embree's thin query only.
const AccelFigures& accelAt(const SceneResult& r, int a) {
    switch (a) {
        case 0: return r.embree;
        case 1: return r.raw;
        case 2: return r.naive;
        case 3: return r.rawFast;
        default: return r.embreeThin;
    }
}

std::string accelLabel(const SceneResult& r, int a) {
    if (a == 0) return "embree";
    if (a == 1) return "raw embree";
    if (a == 3) return "raw, not robust";
    if (a == 4) return "embree single query";
    return "naive (" + std::to_string(r.naive.kinds[size_t(RayKind::Camera)].rays) + " rays)";
}

json timingJson(const Timing& t) { return {{"best", t.best}, {"median", t.median}, {"runs", t.runs}}; }

json rateJson(const RateFigures& f) {
    return {{"rays", f.rays},
            {"mrays_1t", f.mrays1()},
            {"mrays_nt", f.mraysAll()},
            {"seconds_1t", timingJson(f.one)},
            {"seconds_nt", timingJson(f.all)}};
}

json frameJson(const FrameFigures& f) {
    if (!f.measured) return {{"measured", false}, {"note", f.note}};
    return {{"measured", true},
            {"seconds_1t", f.seconds1},
            {"seconds_nt", f.secondsAll},
            {"mrays_1t", f.mrays1()},
            {"mrays_nt", f.mraysAll()},
            {"rays",
             {{"camera", f.rays.camera}, {"shadow", f.rays.shadow}, {"reflection", f.rays.reflection},
              {"transmission", f.rays.transmission}, {"indirect", f.rays.indirect}, {"brdf", f.rays.brdf},
              {"total", f.rays.total()}}}};
}

json optJson(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json disagreementJson(const Disagreement& d) {
    return {{"compared", d.compared}, {"mismatches", d.mismatches}, {"fraction", d.fraction()},
            {"examples", d.examples}};
}

json accelJson(const SceneResult& r, const AccelFigures& a, bool naive) {
    if (!a.present) return nullptr;
    json j;
    j["build_seconds"] = a.buildSeconds;
    j["memory_bytes"] = a.memoryBytes;
    j["bytes_per_triangle"] = r.triangles ? double(a.memoryBytes) / double(r.triangles) : 0.0;
    json kinds;
    for (RayKind k : kRayKinds) {
        json kj = rateJson(a.kinds[size_t(k)]);
        kj["set_rays"] = r.setRays[size_t(k)];
        kinds[rayKindName(k)] = kj;
    }
    j["rays"] = kinds;
    j["frame"] = frameJson(a.frame);
    if (naive) j["note"] = "answers an evenly spread subset of each ray set; rate = subset rays / subset time";
    return j;
}

std::string readCpuModel() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) != 0) continue;
        auto colon = line.find(':');
        if (colon == std::string::npos) continue;
        std::string v = line.substr(colon + 1);
        v.erase(0, v.find_first_not_of(" \t"));
        return v;
    }
    return "unknown CPU";
}

bool findInPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    if (!path) return false;
    std::stringstream ss(path);
    std::string dir;
    while (std::getline(ss, dir, ':')) {
        std::error_code ec;
        const fs::path p = fs::path(dir.empty() ? "." : dir) / program;
        if (fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0) return true;
    }
    return false;
}

// A gnuplot single-quoted string: '' stands for one quote.
std::string gnuplotString(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
    return q + "'";
}

}  // namespace

RunInfo describeMachine(int threads) {
    RunInfo info;
    info.cpu = readCpuModel();
    info.hardwareThreads = hardwareThreads();
    info.threads = threads;
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &utc);
    info.date = buf;
    return info;
}

namespace {

// The scenes and the sizes of their ray sets.
void printScenes(std::FILE* out, const std::vector<SceneResult>& results) {
    std::fprintf(out, "Scenes and ray sets\n");
    std::fprintf(out, "  %-14s %-10s %9s %9s %6s  %8s %8s %8s  %s\n", "scene", "family", "triangles", "prims", "lights",
                 "camera", "shadow", "incoh.", "incoherent = mirror + random");
    for (const auto& r : results)
        std::fprintf(out, "  %-14s %-10s %9zu %9zu %6zu  %8zu %8zu %8zu  %zu + %zu\n", r.name.c_str(),
                     familyName(r.family), r.triangles, r.primitives, r.lights, r.setRays[0], r.setRays[1],
                     r.setRays[2], r.mirrorRays, r.randomRays);
}

// Mrays/s of every accelerator, kind and thread count, and the build figures.
void printRates(std::FILE* out, const std::vector<SceneResult>& results, int T) {
    std::fprintf(out, "\nRates in Mrays/s (1T = one thread, %dT = %d threads); build = BVH build, frame = renderPass\n", T,
                 T);
    std::fprintf(out, "  %-14s %-20s %9s %7s  %7s %7s  %7s %7s  %7s %7s  %9s %9s\n", "scene", "accelerator", "build ms",
                 "B/tri", "cam 1T", ("cam " + std::to_string(T) + "T").c_str(), "shd 1T",
                 ("shd " + std::to_string(T) + "T").c_str(), "inc 1T", ("inc " + std::to_string(T) + "T").c_str(),
                 "frame 1T", ("frame " + std::to_string(T) + "T").c_str());
    for (const auto& r : results) {
        for (int a : {0, 4, 1, 3, 2}) {
            const AccelFigures& f = accelAt(r, a);
            const std::string scene = a == 0 ? r.name : "";
            if ((a == 3 || a == 4) && !f.present) continue;
            if (!f.present) {
                std::fprintf(out, "  %-14s %-20s %s\n", scene.c_str(), accelLabel(r, a).c_str(), f.note.c_str());
                continue;
            }
            // The naive loop builds nothing; the thin query shares embree's structure.
            const std::string build = a == 2 || a == 4 ? "-" : fmt("%.2f", f.buildSeconds * 1e3);
            const std::string bpt = a == 2   ? "0"
                                    : a == 4 ? "-"
                                             : fmt("%.1f", r.triangles ? double(f.memoryBytes) / double(r.triangles) : 0.0);
            const std::string f1 = f.frame.measured ? fmt("%.1f", f.frame.seconds1 * 1e3) : "-";
            const std::string fN = f.frame.measured ? fmt("%.1f", f.frame.secondsAll * 1e3) : "-";
            std::fprintf(out, "  %-14s %-20s %9s %7s  %7s %7s  %7s %7s  %7s %7s  %9s %9s\n", scene.c_str(),
                         accelLabel(r, a).c_str(), build.c_str(), bpt.c_str(), rate(f.kinds[0].mrays1()).c_str(),
                         rate(f.kinds[0].mraysAll()).c_str(), rate(f.kinds[1].mrays1()).c_str(),
                         rate(f.kinds[1].mraysAll()).c_str(), rate(f.kinds[2].mrays1()).c_str(),
                         rate(f.kinds[2].mraysAll()).c_str(), f1.c_str(), fN.c_str());
        }
    }
}

// The ratios against their targets.
void printRatios(std::FILE* out, const std::vector<SceneResult>& results, int T) {
    std::fprintf(out, "\nRatios (renderer = Embree accelerator through the Accelerator interface)\n");
    std::fprintf(out, "  %-14s %9s %9s %9s %9s %9s %9s %9s %9s  %s\n", "scene", "cam/raw1", "cam/rawN", "shd/rawN",
                 "inc/rawN", "frame/q", "renderNT", "build", "memory", "embree/naive (camera, shadow, incoherent, 1T)");
    std::fprintf(out, "  %-14s %9s %9s %9s %9s %9s %9s %9s %9s\n", "target", ">=0.85", ">=0.85", "", "", "<=1.3",
                 ">=1.9", "<=1.1", "<=1.2");
    for (const auto& r : results) {
        const SceneRatios q = ratiosOf(r);
        std::fprintf(out, "  %-14s %9s %9s %9s %9s %9s %9s %9s %9s  %s %s %s\n", r.name.c_str(),
                     opt(q.cameraOverRaw1).c_str(), opt(q.cameraOverRawAll).c_str(), opt(q.kindOverRawAll[1]).c_str(),
                     opt(q.kindOverRawAll[2]).c_str(), opt(q.frameOverQuery).c_str(), opt(q.renderScaling).c_str(),
                     opt(q.buildOverRaw).c_str(), opt(q.memoryOverRaw).c_str(), times(q.embreeOverNaive[0]).c_str(),
                     times(q.embreeOverNaive[1]).c_str(), times(q.embreeOverNaive[2]).c_str());
    }
    std::fprintf(out,
                 "  frame/q = frame time / (sum over the frame's rays of 1 / pure query rate of its kind: raw Embree's, or "
                 "where the scene has analytic shapes the\n  renderer's single-ray intersectPrim/occluded; reflection, "
                 "transmission and BRDF-sampled rays at the incoherent rate), %d threads; "
                 "renderNT = frame throughput %dT / 1T;\n  build = renderer BVH build (own device and shape bounds "
                 "included) / raw scene build (device excluded)\n",
                 T, T);
}

// Raw Embree's packets against its single-ray queries, where the run timed any.
void printPackets(std::FILE* out, const std::vector<SceneResult>& results, int T) {
    bool anyPackets = false;
    for (const auto& r : results) anyPackets = anyPackets || !r.packets.empty();
    if (!anyPackets) return;
    std::fprintf(out, "\nRaw Embree packets (Mrays/s; in brackets: packet rate / rtcIntersect1 or rtcOccluded1 rate)\n");
    std::fprintf(out, "  %-14s %-7s %7s %7s", "scene", "kind", "x1 1T", ("x1 " + std::to_string(T) + "T").c_str());
    std::vector<int> widths;
    for (const auto& r : results)
        for (const auto& p : r.packets)
            if (std::find(widths.begin(), widths.end(), p.width) == widths.end()) widths.push_back(p.width);
    for (int w : widths)
        std::fprintf(out, " %15s %15s", ("x" + std::to_string(w) + " 1T").c_str(),
                     ("x" + std::to_string(w) + " " + std::to_string(T) + "T").c_str());
    std::fprintf(out, "\n");
    for (const auto& r : results) {
        for (RayKind k : {RayKind::Camera, RayKind::Shadow}) {
            bool any = false;
            for (const auto& p : r.packets) any = any || p.kind == k;
            if (!any) continue;
            const RateFigures& single = r.raw.kinds[size_t(k)];
            std::fprintf(out, "  %-14s %-7s %7s %7s", r.name.c_str(), rayKindName(k), rate(single.mrays1()).c_str(),
                         rate(single.mraysAll()).c_str());
            for (int w : widths) {
                std::string c1 = "-", cN = "-";
                for (const auto& p : r.packets) {
                    if (p.kind != k || p.width != w) continue;
                    c1 = rate(p.rate.mrays1()) + " (" + opt(ratio1(p.rate.mrays1(), single.mrays1())) + ")";
                    cN = rate(p.rate.mraysAll()) + " (" + opt(ratio1(p.rate.mraysAll(), single.mraysAll())) + ")";
                }
                std::fprintf(out, " %15s %15s", c1.c_str(), cN.c_str());
            }
            std::fprintf(out, "\n");
        }
    }
    bool native16 = false, native8 = false;
    for (const auto& r : results)
        for (const auto& p : r.packets) {
            if (p.width == 16) native16 = native16 || p.native;
            if (p.width == 8) native8 = native8 || p.native;
        }
    std::fprintf(out, "  this Embree build traces 8-wide packets %s and 16-wide packets %s\n",
                 native8 ? "natively" : "by emulation", native16 ? "natively" : "by emulation");
}

// The accelerators' agreement, with examples of what differed.
void printAgreement(std::FILE* out, const std::vector<SceneResult>& results) {
    const AgreementSummary s = summarizeAgreement(results);
    std::fprintf(out, "\nAgreement (same PrimRef and t within %.0e relative; same occlusion answer; limit %.2f%% of rays)\n",
                 double(kRelativeTolerance), kMaxDisagreement * 100.0);
    std::fprintf(out, "  naive vs embree: %zu of %zu rays differ (%.4f%%)\n", s.naiveVsEmbree.mismatches,
                 s.naiveVsEmbree.compared, s.naiveVsEmbree.fraction() * 100.0);
    std::fprintf(out, "  raw vs embree:   %zu of %zu rays differ (%.4f%%)\n", s.rawVsEmbree.mismatches,
                 s.rawVsEmbree.compared, s.rawVsEmbree.fraction() * 100.0);
    Disagreement fast;
    for (const auto& r : results)
        for (const auto& d : r.rawFastVsEmbree) fast += d;
    std::fprintf(out, "  (not checked) raw without the robust flag vs embree: %zu of %zu rays differ (%.4f%%)\n",
                 fast.mismatches, fast.compared, fast.fraction() * 100.0);
    for (const auto& r : results)
        for (size_t k = 0; k < kRayKindCount; ++k) {
            for (const auto& e : r.naiveVsEmbree[k].examples)
                std::fprintf(out, "    %s naive vs embree: %s\n", r.name.c_str(), e.c_str());
            for (const auto& e : r.rawVsEmbree[k].examples)
                std::fprintf(out, "    %s raw vs embree: %s\n", r.name.c_str(), e.c_str());
        }
    std::fprintf(out, "agreement: %s\n", s.passed() ? "passed" : "FAILED");
}

}  // namespace

void printReport(std::FILE* out, const std::vector<SceneResult>& results, const BenchOptions& o, const RunInfo& info) {
    const int T = info.threads;
    std::fprintf(out, "penumbra-bench: %s, %d hardware threads; multi-threaded runs use %d\n", info.cpu.c_str(),
                 info.hardwareThreads, T);
    std::fprintf(out,
                 "  %zu camera rays per scene, best of %d runs after a warm-up; naive: at most %zu rays per kind, "
                 "one run each\n\n",
                 o.rays, o.repetitions, o.naiveMaxRays);
    printScenes(out, results);
    printRates(out, results, T);
    printRatios(out, results, T);
    printPackets(out, results, T);
    printAgreement(out, results);
}

namespace {

// Every accelerator's figures for one scene.
json acceleratorsJson(const SceneResult& r) {
    json accels;
    accels["embree"] = accelJson(r, r.embree, false);
    accels["naive"] = accelJson(r, r.naive, true);
    json raw = accelJson(r, r.raw, false);
    if (r.raw.present) {
        raw["device_seconds"] = r.raw.deviceSeconds;
        json packets;
        for (const auto& p : r.packets) {
            json pj = rateJson(p.rate);
            pj["native"] = p.native;
            pj["speedup_1t"] = optJson(ratio1(p.rate.mrays1(), r.raw.kinds[size_t(p.kind)].mrays1()));
            pj["speedup_nt"] = optJson(ratio1(p.rate.mraysAll(), r.raw.kinds[size_t(p.kind)].mraysAll()));
            packets[rayKindName(p.kind)][std::to_string(p.width)] = pj;
        }
        raw["packets"] = packets;
    } else {
        raw = {{"note", r.raw.note}};
    }
    json thin;
    for (RayKind k : kRayKinds) thin[rayKindName(k)] = rateJson(r.embreeThin.kinds[size_t(k)]);
    accels["embree_intersect_prim"] = {
        {"note", "the renderer's accelerator answering single rays with nothing else: intersectPrim (no hit "
                 "completion) for closest-hit kinds, occluded() for shadow rays"},
        {"rays", thin}};
    accels["raw_embree"] = raw;
    if (r.rawFast.present) {
        json fast = accelJson(r, r.rawFast, false);
        fast["note"] = "raw Embree without RTC_SCENE_FLAG_ROBUST; disagreements reported, not checked";
        json agreeFast;
        for (size_t k = 0; k < kRayKindCount; ++k)
            agreeFast[rayKindName(kRayKinds[k])] = disagreementJson(r.rawFastVsEmbree[k]);
        fast["agreement_with_embree"] = agreeFast;
        accels["raw_embree_not_robust"] = fast;
    } else {
        accels["raw_embree_not_robust"] = nullptr;
    }
    return accels;
}

// The ratios for one scene.
json ratiosJson(const SceneResult& r) {
    const SceneRatios q = ratiosOf(r);
    json ratios = {{"camera_renderer_over_raw_1t", optJson(q.cameraOverRaw1)},
                   {"camera_renderer_over_raw_nt", optJson(q.cameraOverRawAll)},
                   {"frame_over_query_nt", optJson(q.frameOverQuery)},
                   {"render_scaling_nt_over_1t", optJson(q.renderScaling)},
                   {"build_renderer_over_raw", optJson(q.buildOverRaw)},
                   {"build_renderer_over_raw_with_device", optJson(q.buildOverRawWithDevice)},
                   {"memory_renderer_over_raw", optJson(q.memoryOverRaw)}};
    for (size_t k = 0; k < kRayKindCount; ++k) {
        ratios["renderer_over_raw_nt"][rayKindName(kRayKinds[k])] = optJson(q.kindOverRawAll[k]);
        ratios["embree_over_naive_1t"][rayKindName(kRayKinds[k])] = optJson(q.embreeOverNaive[k]);
        ratios["raw_not_robust_over_raw_nt"][rayKindName(kRayKinds[k])] = optJson(q.notRobustOverRaw[k]);
    }
    return ratios;
}

json sceneJson(const SceneResult& r) {
    json s;
    s["name"] = r.name;
    s["family"] = familyName(r.family);
    s["triangles"] = r.triangles;
    s["primitives"] = r.primitives;
    s["lights"] = r.lights;
    s["triangle_only"] = r.triangleOnly;
    s["prepare_seconds"] = r.prepareSeconds;
    s["ray_sets"] = {{"camera", r.setRays[0]},     {"shadow", r.setRays[1]},   {"incoherent", r.setRays[2]},
                     {"image_side", r.imageSide},  {"camera_hits", r.cameraHits},
                     {"mirror", r.mirrorRays},     {"random", r.randomRays}};
    s["accelerators"] = acceleratorsJson(r);

    json agree;
    for (size_t k = 0; k < kRayKindCount; ++k) {
        agree["naive_vs_embree"][rayKindName(kRayKinds[k])] = disagreementJson(r.naiveVsEmbree[k]);
        agree["raw_vs_embree"][rayKindName(kRayKinds[k])] = disagreementJson(r.rawVsEmbree[k]);
    }
    s["agreement"] = agree;

    s["ratios"] = ratiosJson(r);
    return s;
}

}  // namespace

json toJson(const std::vector<SceneResult>& results, const BenchOptions& o, const RunInfo& info) {
    json j;
    j["tool"] = "penumbra-bench";
    j["format_version"] = 1;
    j["date"] = info.date;
    j["command"] = o.commandLine;
    j["total_seconds"] = info.totalSeconds;
    j["machine"] = {{"cpu", info.cpu}, {"hardware_threads", info.hardwareThreads}};
    j["settings"] = {{"threads", info.threads},
                     {"rays", o.rays},
                     {"naive_max_rays", o.naiveMaxRays},
                     {"naive_budget_triangle_tests", o.naiveBudget},
                     {"repetitions", o.repetitions},
                     {"quick", o.quick},
                     {"seed", o.seed},
                     {"frame",
                      {{"width", o.frameWidth},
                       {"height", o.frameHeight},
                       {"spp", o.frameSpp},
                       {"light_samples", o.frameLightSamples},
                       {"max_depth", o.frameMaxDepth}}}};
    json scenes = json::array();
    for (const auto& r : results) scenes.push_back(sceneJson(r));
    j["scenes"] = scenes;
    const AgreementSummary a = summarizeAgreement(results);
    j["agreement"] = {{"naive_vs_embree", disagreementJson(a.naiveVsEmbree)},
                      {"raw_vs_embree", disagreementJson(a.rawVsEmbree)},
                      {"relative_tolerance", kRelativeTolerance},
                      {"max_fraction", kMaxDisagreement},
                      {"passed", a.passed()}};
    j["targets"] = {{"camera_renderer_over_raw_min", 0.85},
                    {"frame_over_query_max", 1.3},
                    {"render_scaling_min", 1.9},
                    {"build_renderer_over_raw_max", 1.1},
                    {"memory_renderer_over_raw_max", 1.2}};
    return j;
}

std::string writePlot(const fs::path& png, const std::vector<SceneResult>& results, const RunInfo& info) {
    std::vector<const SceneResult*> series;
    for (const auto& r : results)
        if (r.family == SceneFamily::Procedural && r.raw.present && r.naive.present) series.push_back(&r);
    if (series.empty()) return "no procedural scenes to plot";
    std::sort(series.begin(), series.end(), [](auto* a, auto* b) { return a->triangles < b->triangles; });

    fs::path data = png;
    data.replace_extension(".tsv");
    {
        std::ofstream out(data);
        out << "# penumbra-bench " << info.date << ": Mrays/s with " << info.threads
            << " threads against triangle count;\n# one block per accelerator and ray kind (scripts/plot_bench.gp)\n";
        for (int a = 0; a < 3; ++a)
            for (RayKind k : kRayKinds) {
                out << "\"" << kAccelNames[a] << " " << rayKindName(k) << "\"\n";
                for (const SceneResult* r : series) out << r->triangles << "\t" << accelAt(*r, a).kinds[size_t(k)].mraysAll() << "\n";
                out << "\n\n";
            }
        if (!out) return data.string() + ": cannot write the plot data";
    }
    if (!findInPath("gnuplot")) return "gnuplot not found; no plot written (scripts/setup.sh installs gnuplot-nox)";
    std::error_code ec;
    fs::remove(png, ec);  // so a stale file cannot pass for this run's plot
    std::FILE* gp = ::popen("gnuplot", "w");
    if (!gp) return "cannot start gnuplot; no plot written";
    const std::string title = "penumbra-bench, " + std::to_string(info.threads) + " threads, " + info.cpu;
    std::fprintf(gp, "datafile = %s\noutfile = %s\nplottitle = %s\n", gnuplotString(data.string()).c_str(),
                 gnuplotString(png.string()).c_str(), gnuplotString(title).c_str());
    std::fputs(kPlotScript, gp);
    const int status = ::pclose(gp);
    if (status != 0 || !fs::exists(png)) return "gnuplot failed; no plot written";
    return "";
}

}  // namespace penumbra::bench
