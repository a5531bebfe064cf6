// contact_studies.cpp: placeholder until the studies are written (issue 25).
#include "stability_study.hpp"

namespace bemsurg::bench::stability {
nlohmann::json study_thin(const StudyContext&) { throw Error("study thin: not written yet"); }
nlohmann::json study_depth(const StudyContext&) { throw Error("study depth: not written yet"); }
}  // namespace bemsurg::bench::stability
