#include "real_photos.hpp"

#include "ball_detector/core/evaluation.hpp"
#include "common/util/bench_clock.hpp"
#include "interleaved_timing.hpp"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

namespace stereoball::bench_detect {
namespace bd = ball_detector;
namespace fs = std::filesystem;

namespace {

// A setting tying on tune F1 replaces an earlier one only when at least this much faster.
constexpr double kClearlyFaster = 0.9;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

std::variant<std::vector<LabelledImage>, std::string> load_labelled_images(
    const fs::path& dir, const fs::path& project_root) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return "no label folder '" + dir.string() + "'";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".circles") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) return "no *.circles file in '" + dir.string() + "'";
  std::vector<LabelledImage> out;
  for (const auto& f : files) {
    std::ifstream in(f);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) return "cannot read '" + f.string() + "'";
    auto parsed = bd::parse_circle_labels(text.str(), f.string());
    if (auto* e = std::get_if<std::string>(&parsed)) return *e;
    auto& labels = std::get<bd::CircleLabels>(parsed);
    const fs::path image_path = project_root / labels.image_path;
    cv::Mat image = cv::imread(image_path.string(), cv::IMREAD_COLOR);
    if (image.empty()) return f.string() + ": cannot read image '" + image_path.string() + "'";
    const double min_radius =
        labels.min_radius_px.value_or(kDefaultMinRadiusPerSide * std::min(image.cols, image.rows));
    out.push_back({f.stem().string(), image, std::move(labels.circles), labels.split, min_radius});
  }
  return out;
}

double RealScore::f1() const {
  return bd::detection_scores(tp, fp, fn).f1;
}

RealScore score_setting(const Setting& setting, const std::vector<LabelledImage>& images,
                        bd::LabelSplit split, int repeats, double min_iou, bool explain) {
  RealScore s;
  for (const auto& img : images) {
    if (img.split != split) continue;
    auto det = setting.make(img.image.size(), img.min_radius_px);
    det->detect(img.image);  // warm-up: first-call allocations
    std::vector<double> ms;
    std::vector<bd::Circle> found;
    for (int r = 0; r < repeats; ++r) {
      const double t0 = bench::thread_cpu_ms();
      found = det->detect(img.image);
      ms.push_back(bench::thread_cpu_ms() - t0);
    }
    s.image_ms.push_back(median(ms));
    const auto m = bd::match_circles(found, img.truth, min_iou);
    if (explain && (m.false_negatives > 0 || m.false_positives > 0)) {
      std::printf("  %s %s: tp %d fp %d fn %d |", setting.label.c_str(), img.name.c_str(),
                  m.true_positives, m.false_positives, m.false_negatives);
      for (const auto& c : found)
        std::printf(" found(%.1f,%.1f,%.1f,%.2f)", c.x_px, c.y_px, c.radius_px, c.score);
      std::printf("\n");
    }
    s.tp += m.true_positives;
    s.fp += m.false_positives;
    s.fn += m.false_negatives;
    s.errors_px.insert(s.errors_px.end(), m.centre_errors_px.begin(), m.centre_errors_px.end());
  }
  return s;
}

void print_detections(const std::string& row, const Setting& setting,
                      const std::vector<LabelledImage>& images) {
  for (const auto& img : images) {
    auto det = setting.make(img.image.size(), img.min_radius_px);
    std::printf("  detections %s | %s:", row.c_str(), img.name.c_str());
    for (const auto& c : det->detect(img.image))
      std::printf(" %.3f %.3f %.3f %.3f", c.x_px, c.y_px, c.radius_px, c.score);
    std::printf("\n");
  }
}

Breakdown tune_breakdown(const Setting& setting, const std::vector<LabelledImage>& images,
                         double min_iou) {
  Breakdown b;
  for (const auto& img : images) {
    if (img.split != bd::LabelSplit::tune) continue;
    auto det = setting.make(img.image.size(), img.min_radius_px);
    const std::vector<bd::Circle> found = det->detect(img.image);
    const auto m = bd::match_circles(found, img.truth, min_iou);
    Breakdown::Image row{img.name, static_cast<int>(img.truth.size()), m.true_positives,
                         m.false_positives, 1e9};
    for (const auto& t : img.truth) {
      row.min_truth_radius_px = std::min(row.min_truth_radius_px, t.radius_px);
      std::size_t band = 0;
      while (band + 2 < kBreakdownBandsPx.size() && t.radius_px >= kBreakdownBandsPx[band + 1])
        ++band;
      ++b.truth[band];
      b.found[band] += std::any_of(found.begin(), found.end(), [&](const bd::Circle& c) {
        return bd::circle_iou(c, t) >= min_iou;
      });
    }
    if (img.truth.empty()) row.min_truth_radius_px = 0.0;
    b.images.push_back(row);
  }
  return b;
}

namespace {

void print_breakdown(const std::string& family, const std::string& setting, const Breakdown& b) {
  std::printf("  tune split, %s (%s): labelled circles found by radius\n", family.c_str(),
              setting.c_str());
  for (std::size_t i = 0; i < b.truth.size(); ++i)
    std::printf(
        "    r in [%3.0f, %s): %3d of %3d\n", kBreakdownBandsPx[i],
        i + 1 < b.truth.size() ? cv::format("%3.0f", kBreakdownBandsPx[i + 1]).c_str() : "inf",
        b.found[i], b.truth[i]);
  std::printf("    per image: name, labelled (smallest r), tp, fp\n");
  for (const auto& im : b.images)
    std::printf("    %-40s %3d (%5.1f) %3d %3d\n", im.name.c_str(), im.truth,
                im.min_truth_radius_px, im.tp, im.fp);
}

// The setting with the best tune F1 among those whose median tune time is at most max_ms; a
// tie goes to the earlier setting unless a later one is clearly faster (a tie on time noise
// alone made the choice, and the report figure, change from run to run). -1: none qualifies.
int choose_on_tune(const std::vector<RealScore>& tune, double max_ms) {
  int best = -1;
  for (std::size_t i = 0; i < tune.size(); ++i) {
    const RealScore& s = tune[i];
    if (median(s.image_ms) > max_ms) continue;
    const RealScore* b = best < 0 ? nullptr : &tune[static_cast<std::size_t>(best)];
    const bool better =
        !b || s.f1() > b->f1() + 1e-9 ||
        (s.f1() > b->f1() - 1e-9 && median(s.image_ms) < kClearlyFaster * median(b->image_ms));
    if (better) best = static_cast<int>(i);
  }
  return best;
}

// Median per-image time of a and of b on the tune split, timed side by side: per image both
// detectors made and warmed up, then `repeats` alternating runs of each (a busy machine slows
// both alike). Returns {a ms, b ms}.
std::pair<double, double> side_by_side_tune_ms(const Setting& a, const Setting& b,
                                               const std::vector<LabelledImage>& images,
                                               int repeats) {
  std::vector<double> a_ms, b_ms;
  for (const auto& img : images) {
    if (img.split != bd::LabelSplit::tune) continue;
    auto da = a.make(img.image.size(), img.min_radius_px);
    auto db = b.make(img.image.size(), img.min_radius_px);
    da->detect(img.image);
    db->detect(img.image);
    std::vector<double> ra, rb;
    for (int r = 0; r < repeats; ++r) {
      double t0 = bench::thread_cpu_ms();
      da->detect(img.image);
      ra.push_back(bench::thread_cpu_ms() - t0);
      t0 = bench::thread_cpu_ms();
      db->detect(img.image);
      rb.push_back(bench::thread_cpu_ms() - t0);
    }
    a_ms.push_back(median(ra));
    b_ms.push_back(median(rb));
  }
  return {median(a_ms), median(b_ms)};
}

// The time-capped choice: the first family's settings by decreasing tune F1 (ties: the earlier
// first), those within kCapScreen of the cap in the sweep's one-run times re-timed side by side
// with the cap setting on the tune split; the first no slower there wins. At most
// kCapCandidates are re-timed. -1: none.
constexpr double kCapScreen = 1.5;
constexpr int kCapCandidates = 40;
int choose_time_capped(const Family& family, const std::vector<RealScore>& tune, const Setting& cap,
                       double cap_sweep_ms, const std::vector<LabelledImage>& images, int repeats,
                       double& ratio) {
  std::vector<std::size_t> order(tune.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return tune[x].f1() > tune[y].f1(); });
  int tried = 0;
  for (const std::size_t i : order) {
    if (median(tune[i].image_ms) > kCapScreen * cap_sweep_ms) continue;
    if (tried++ >= kCapCandidates) break;
    const auto [ms, cap_ms] = side_by_side_tune_ms(family.settings[i], cap, images, repeats);
    if (ms <= cap_ms) {
      ratio = ms / std::max(1e-9, cap_ms);
      return static_cast<int>(i);
    }
  }
  return -1;
}

void print_time_cap_note(const std::string& family, const std::string& cap_family, double ratio,
                         bool found) {
  if (!found) {
    std::printf("%s <= %s: no %s setting is as fast as %s on the tune split\n", family.c_str(),
                cap_family.c_str(), family.c_str(), cap_family.c_str());
    return;
  }
  std::printf(
      "%s <= %s: the best tune F1 among the %s settings no slower than %s's chosen setting on "
      "the tune split, timed side by side per image (median ms ratio there %.2f); chosen on "
      "the tune split only\n",
      family.c_str(), cap_family.c_str(), family.c_str(), cap_family.c_str(), ratio);
}

// A row's setting, for the interleaved timing after the table.
struct ChosenSetting {
  std::string name;
  const Setting* setting;
};

// The chosen settings timed interleaved on the report split (time_interleaved: per image each
// in turn, `repeats` rounds), then the first row's ratio to every other row with its spread.
// The table's ms/img column times each setting alone, minutes apart on a shared machine; the
// ratios come from here. Fills each row's interleaved_ms.
void print_interleaved_times(const std::vector<ChosenSetting>& chosen,
                             const std::vector<LabelledImage>& images, int repeats,
                             std::vector<RealRow>& rows) {
  if (chosen.size() < 2) return;
  std::vector<const LabelledImage*> report;
  for (const auto& img : images)
    if (img.split == bd::LabelSplit::report) report.push_back(&img);
  std::vector<std::unique_ptr<bd::CircleDetector>> detectors(chosen.size());
  const TimedMethods calls{
      [&](int i) {
        const LabelledImage& img = *report[static_cast<std::size_t>(i)];
        for (std::size_t m = 0; m < chosen.size(); ++m)
          detectors[m] = chosen[m].setting->make(img.image.size(), img.min_radius_px);
      },
      [&](int m, int i) {
        detectors[static_cast<std::size_t>(m)]->detect(report[static_cast<std::size_t>(i)]->image);
      }};
  const InterleavedTimes t =
      time_interleaved(static_cast<int>(chosen.size()), static_cast<int>(report.size()), repeats,
                       calls, [] { return bench::thread_cpu_ms(); });
  std::printf(
      "\nInterleaved on the report split (per image every row's setting in turn, %d rounds, "
      "round r starting with the r-th row; median per image, then over images; thread CPU, "
      "1 thread):\n",
      repeats);
  for (std::size_t m = 0; m < chosen.size(); ++m) {
    rows[m].interleaved_ms = t.median_ms(static_cast<int>(m));
    std::printf("  %-22s %8.2f ms\n", chosen[m].name.c_str(), rows[m].interleaved_ms);
  }
  for (std::size_t m = 1; m < chosen.size(); ++m)
    std::printf("time %s / %s, interleaved: %s\n", chosen.front().name.c_str(),
                chosen[m].name.c_str(),
                format_ratio(time_ratio(t, 0, static_cast<int>(m))).c_str());
}

}  // namespace

std::vector<RealRow> run_real_photo_table(const std::vector<Family>& families,
                                          const std::vector<LabelledImage>& images, int repeats,
                                          double min_iou, bool verbose, bool breakdown,
                                          const std::string& time_cap_family,
                                          bool print_all_detections) {
  auto count = [&](bd::LabelSplit split, bool circles) {
    size_t n = 0;
    for (const auto& i : images)
      if (i.split == split) n += circles ? i.truth.size() : 1;
    return n;
  };
  std::printf(
      "\nReal photographs (tests/data/circles): settings chosen on the tune split (%zu images, "
      "%zu circles), reported on the report split (%zu images, %zu circles), never tuned on; "
      "IoU >= %.2f; ms = median over images of the median of %d runs, thread CPU, 1 thread, "
      "edges included.\n",
      count(bd::LabelSplit::tune, false), count(bd::LabelSplit::tune, true),
      count(bd::LabelSplit::report, false), count(bd::LabelSplit::report, true), min_iou, repeats);
  std::printf("%-22s %-34s %7s | %6s %6s %6s %8s %8s\n", "method", "best setting on tune", "tuneF1",
              "P", "R", "F1", "err_px", "ms/img");
  // Every family's tune sweep first: the time-capped choice needs the cap family's time.
  std::vector<std::vector<RealScore>> tune(families.size());
  std::vector<int> best(families.size(), -1);
  for (std::size_t fi = 0; fi < families.size(); ++fi) {
    const Family& family = families[fi];
    for (const auto& setting : family.settings) {
      tune[fi].push_back(score_setting(setting, images, bd::LabelSplit::tune, 1, min_iou, false));
      if (verbose)
        std::printf("  tune %-22s %-34s F1 %.3f ms %.2f\n", family.name.c_str(),
                    setting.label.c_str(), tune[fi].back().f1(), median(tune[fi].back().image_ms));
    }
    best[fi] = choose_on_tune(tune[fi], std::numeric_limits<double>::infinity());
  }
  // The first family again, among its settings no slower on the tune split than the cap
  // family's chosen setting there (same run, same images).
  int capped = -1;
  double cap_ms = 0.0;
  bool cap_present = false;
  double cap_ratio = 0.0;
  if (!time_cap_family.empty() && !families.empty())
    for (std::size_t fi = 1; fi < families.size(); ++fi)
      if (families[fi].name == time_cap_family && best[fi] >= 0) {
        cap_present = true;
        cap_ms = median(tune[fi][static_cast<std::size_t>(best[fi])].image_ms);
        capped = choose_time_capped(families[0], tune[0],
                                    families[fi].settings[static_cast<std::size_t>(best[fi])],
                                    cap_ms, images, repeats, cap_ratio);
      }
  std::vector<RealRow> rows;
  std::vector<ChosenSetting> chosen_settings;
  const auto report = [&](std::size_t fi, int chosen, const std::string& name) {
    const Setting& setting = families[fi].settings[static_cast<std::size_t>(chosen)];
    chosen_settings.push_back({name, &setting});
    const RealScore& t = tune[fi][static_cast<std::size_t>(chosen)];
    const RealScore r =
        score_setting(setting, images, bd::LabelSplit::report, repeats, min_iou, verbose);
    const auto sc = bd::detection_scores(r.tp, r.fp, r.fn);
    std::printf("%-22s %-34s %7.3f | %6.3f %6.3f %6.3f %8.3f %8.2f\n", name.c_str(),
                setting.label.c_str(), t.f1(), sc.precision, sc.recall, sc.f1, median(r.errors_px),
                median(r.image_ms));
    rows.push_back({name, setting.label, t.f1(), sc.f1, median(r.image_ms), median(t.image_ms)});
    if (breakdown) print_breakdown(name, setting.label, tune_breakdown(setting, images, min_iou));
    if (print_all_detections) print_detections(name, setting, images);
  };
  for (std::size_t fi = 0; fi < families.size(); ++fi) {
    if (best[fi] < 0) continue;
    report(fi, best[fi], families[fi].name);
    if (fi == 0 && capped >= 0) report(0, capped, families[0].name + " <= " + time_cap_family);
  }
  if (cap_present && best[0] >= 0)
    print_time_cap_note(families[0].name, time_cap_family, cap_ratio, capped >= 0);
  print_interleaved_times(chosen_settings, images, repeats, rows);
  // The time-capped row against the cap family, on both splits.
  const auto row_of = [&](const std::string& name) -> const RealRow* {
    for (const auto& row : rows)
      if (row.family == name) return &row;
    return nullptr;
  };
  if (capped >= 0)
    if (const RealRow* a = row_of(families[0].name + " <= " + time_cap_family),
        *b = row_of(time_cap_family);
        a && b)
      std::printf("time %s / %s: tune split %.2f, report split %.2f\n", a->family.c_str(),
                  b->family.c_str(), a->tune_ms / std::max(1e-9, b->tune_ms),
                  a->report_ms / std::max(1e-9, b->report_ms));
  return rows;
}

}  // namespace stereoball::bench_detect
