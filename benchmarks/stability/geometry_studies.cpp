// geometry_studies.cpp: placeholder until the studies are written (issue 25).
#include "stability_study.hpp"

namespace bemsurg::bench::stability {
nlohmann::json study_interior(const StudyContext&) { throw Error("study interior: not written yet"); }
nlohmann::json study_sliver(const StudyContext&) { throw Error("study sliver: not written yet"); }
}  // namespace bemsurg::bench::stability
