// stability_study.hpp: what the nine stability studies of bench_stability share (issue 25,
// docs/stability.md). Each study sweeps one parameter until a method breaks, writes its sweep as
// CSV (one column per parameter, then one per metric, SI units, errors as fractions: the report's
// schema, docs/benchmarks.md) and returns a JSON summary naming the threshold it found and the
// library behaviour that applies there.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg::bench::stability {

/// What a study is given: --quick (a seconds-long sweep: ctest's smoke run and the report's
/// --quick) and the folder its CSV files go to.
struct StudyContext {
  bool quick = false;
  std::filesystem::path csv_dir = ".";
};

/// One CSV file of a study: the header once, then rows of numbers or strings. Numbers are written
/// in the shortest form that reads back exactly, in the classic locale (number_text.hpp); NaN or infinity as an empty cell ("not
/// measured"), never as text a reader would parse as a number.
class CsvTable {
 public:
  using Cell = std::variant<double, std::string>;
  CsvTable(const std::filesystem::path& path, std::initializer_list<const char*> columns) : path_(path), columns_(columns.size()) {
    out_.open(path);
    if (!out_) throw IoError("bench_stability: cannot write " + path.string());
    const char* sep = "";
    for (const char* c : columns) {
      out_ << sep << c;
      sep = ",";
    }
    out_ << "\n";
  }
  void row(std::initializer_list<Cell> cells) {
    if (cells.size() != columns_)
      throw InvalidArgumentError("bench_stability: a row of " + path_.string() + " has the wrong number of cells");
    const char* sep = "";
    for (const Cell& c : cells) {
      out_ << sep;
      if (const double* x = std::get_if<double>(&c)) {
        if (std::isfinite(*x)) out_ << number_text(*x);
      } else {
        out_ << std::get<std::string>(c);
      }
      sep = ",";
    }
    out_ << "\n";
    out_.flush();
  }

 private:
  std::filesystem::path path_;
  std::size_t columns_;
  std::ofstream out_;
};

using StudyFunction = nlohmann::json (*)(const StudyContext&);

/// One study: its letter in issue 25, the name --study takes, and what it sweeps.
struct StudyEntry {
  const char* letter;
  const char* name;
  const char* title;
  StudyFunction run;
};

// One translation unit per group of studies (benchmarks/stability/*.cpp).
nlohmann::json study_poisson(const StudyContext& ctx);   // (a) solvers_studies.cpp
nlohmann::json study_krylov(const StudyContext& ctx);    // (e) solvers_studies.cpp
nlohmann::json study_interior(const StudyContext& ctx);  // (b) geometry_studies.cpp
nlohmann::json study_sliver(const StudyContext& ctx);    // (c) geometry_studies.cpp
nlohmann::json study_gap(const StudyContext& ctx);       // (d) cutting_studies.cpp
nlohmann::json study_updates(const StudyContext& ctx);   // (f) cutting_studies.cpp
nlohmann::json study_thin(const StudyContext& ctx);      // (g) contact_studies.cpp
nlohmann::json study_depth(const StudyContext& ctx);     // (h) contact_studies.cpp
nlohmann::json study_grading(const StudyContext& ctx);   // (i) grading_studies.cpp

/// The studies in the order of issue 25 and docs/stability.md.
inline const std::vector<StudyEntry>& all_studies() {
  static const std::vector<StudyEntry> studies = {
      {"a", "poisson", "Poisson's ratio towards 0.5", study_poisson},
      {"b", "interior", "interior points approaching the surface", study_interior},
      {"c", "sliver", "sliver triangles", study_sliver},
      {"d", "gap", "cut gap width against element size", study_gap},
      {"e", "krylov", "GMRES restart, BiCG and BiCGStab breakdowns", study_krylov},
      {"f", "updates", "accumulated low-rank updates after many cut steps", study_updates},
      {"g", "thin", "thin parts and tool size against element size", study_thin},
      {"h", "depth", "press depth against tool radius", study_depth},
      {"i", "grading", "non-uniform meshes", study_grading},
  };
  return studies;
}

}  // namespace bemsurg::bench::stability
