// Reading and writing the ground-truth relations of the SLAM benchmark of
// Kuemmerle et al. 2009 ("On measuring the accuracy of SLAM algorithms"), as
// distributed with the Freiburg/Radish datasets (e.g. aces.relations):
//
//   t1 t2 x y z roll pitch yaw
//
// one relation per line: stamps in seconds (read exactly to the nanosecond),
// and the displacement of the pose at t2 expressed in the frame of the pose
// at t1 (as Cartographer's relations_text_file.cc reads them): translation in
// metres, rotation R = Rz(yaw) Ry(pitch) Rx(roll) in radians. Blank lines and
// '#' comments are skipped.
//
// Errors: "PATH:LINE: problem" (field count, bad or non-finite number, a bad
// stamp); a file without relations is an error. The writer prints numbers
// in shortest round-trip digits and stamps exactly, through a temporary file.
#ifndef SLAM_DATASETS_RELATIONS_IO_H_
#define SLAM_DATASETS_RELATIONS_IO_H_

#include <string>
#include <vector>

#include "core/metrics/relation_error.h"

namespace slam {

// *lines (optional) receives the line of each relation.
bool ReadRelations(const std::string& path,
                   std::vector<PoseRelation>* relations, std::string* error,
                   std::vector<int>* lines = nullptr);

bool WriteRelations(const std::string& path,
                    const std::vector<PoseRelation>& relations,
                    std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_RELATIONS_IO_H_
