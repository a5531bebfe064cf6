// cutting_studies.cpp: placeholder until the studies are written (issue 25).
#include "stability_study.hpp"

namespace bemsurg::bench::stability {
nlohmann::json study_gap(const StudyContext&) { throw Error("study gap: not written yet"); }
nlohmann::json study_updates(const StudyContext&) { throw Error("study updates: not written yet"); }
}  // namespace bemsurg::bench::stability
