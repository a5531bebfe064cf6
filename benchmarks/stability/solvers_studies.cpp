// solvers_studies.cpp: placeholder until the studies are written (issue 25).
#include "stability_study.hpp"

namespace bemsurg::bench::stability {
nlohmann::json study_poisson(const StudyContext&) { throw Error("study poisson: not written yet"); }
nlohmann::json study_krylov(const StudyContext&) { throw Error("study krylov: not written yet"); }
}  // namespace bemsurg::bench::stability
