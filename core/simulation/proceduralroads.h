/***************************************************************************
  proceduralroads.h - the roads of the procedural scenes
  -------------------------------------------------------------------------
  Highway: a dual carriageway (2 x 2 lanes of 3.5 m) with a 30° curve of
  220 m radius to the left and a 20° curve of 300 m to the right, and a side
  road leaving it northwards. Aerial and oblique scenes: a two-lane road with an
  S-bend, a side road at a junction and a third road leaving northwards
  with a bend. All in the block CRS around the site centre, 2 m vertices
  on the arcs.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_PROCEDURALROADS_H
#define GEOSTATION_SIMULATION_PROCEDURALROADS_H

#include <vector>

#include <Eigen/Core>

#include "simulation/roadnetwork.h"
#include "simulation/scenebuilder.h"

namespace geostation
{
  //! Procedural roads around the site centre (block CRS) for a preset.
  std::vector<Road> proceduralRoads( SurveyPreset preset, const Eigen::Vector2d &centre );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_PROCEDURALROADS_H
