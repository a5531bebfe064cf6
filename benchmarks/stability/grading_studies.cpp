// grading_studies.cpp: placeholder until the studies are written (issue 25).
#include "stability_study.hpp"

namespace bemsurg::bench::stability {
nlohmann::json study_grading(const StudyContext&) { throw Error("study grading: not written yet"); }
}  // namespace bemsurg::bench::stability
