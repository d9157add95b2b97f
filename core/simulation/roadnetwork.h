/***************************************************************************
  roadnetwork.h - roads of the simulated scene and their painted markings
  -------------------------------------------------------------------------
  A road is a centre line in the block CRS (x, y), a number of lanes per
  direction and a lane width. A ground point is located on the road by its
  station s (metres along the centre line) and its offset d (metres, positive
  to the left of the direction of digitising). Markings follow the usual
  layout: centre line (solid or dashed, 0.15 m), lane separators (dashed
  3 m / 9 m), edge lines (solid, 0.15 m, 0.3 m inside the edge), and a
  concrete kerb 0.25 m wide outside the asphalt.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_ROADNETWORK_H
#define GEOSTATION_SIMULATION_ROADNETWORK_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "simulation/spatialgrid.h"

namespace geostation
{

  struct Road
  {
    std::string id;
    std::vector<Eigen::Vector2d> centreline; //!< block CRS, at least two vertices
    int lanesPerDirection = 1;
    double laneWidthM = 3.5;
    bool dashedCentre = false;

    double halfWidthM() const { return lanesPerDirection * laneWidthM; }
  };

  //! A painted line of a road, as the offset band [offset - width/2, offset + width/2].
  struct RoadMarkingLine
  {
    std::string kind;   //!< "centre", "separator" or "edge_line"
    double offsetM = 0.0;
    double widthM = 0.15;
    bool dashed = false;
  };

  constexpr double kKerbWidthM = 0.25;
  constexpr double kShoulderWidthM = 1.5; //!< gravel beyond the kerb
  constexpr double kDashM = 3.0, kGapM = 9.0;
  constexpr double kBlendReachM = 14.0; //!< terrain blends from road level to open ground over this distance

  //! The markings of a road, centre first.
  std::vector<RoadMarkingLine> roadMarkings( const Road &road );

  //! Where a ground point lies on a road.
  struct RoadLocation
  {
    int road = -1;
    double s = 0.0;   //!< metres along the centre line
    double d = 0.0;   //!< metres to the left of the centre line
  };

  class RoadNetwork
  {
    public:
      RoadNetwork() = default;
      /**
       * Roads in priority order: where two overlap (a junction), the earlier
       * one is on top. Centre lines are densified to 10 m. Throws
       * std::invalid_argument for a road with fewer than two distinct vertices.
       */
      explicit RoadNetwork( std::vector<Road> roads );

      /**
       * The nearest point of any road's centre line within `maxDistanceM`
       * (at most the shoulder's outer edge plus kBlendReachM).
       */
      std::optional<RoadLocation> nearestCentreline( double x, double y, double maxDistanceM ) const;

      const std::vector<Road> &roads() const { return mRoads; }
      //! roadMarkings() of each road, computed once.
      const std::vector<RoadMarkingLine> &markings( int road ) const { return mMarkings[road]; }
      double length( int road ) const { return mCumulative[road].back(); }

      /**
       * The road a ground point belongs to: the first road (priority order)
       * whose asphalt, kerb or shoulder it is on, with its (s, d); nothing
       * further from every road.
       */
      std::optional<RoadLocation> locate( double x, double y ) const;

      //! Whether (x, y) is on the asphalt of a road other than `road` that has priority over it.
      bool onHigherPriorityRoad( int road, double x, double y ) const;

      //! The ground point at station s (clamped) and offset d of a road, and the unit tangent there.
      Eigen::Vector2d pointAt( int road, double s, double d, Eigen::Vector2d *tangent = nullptr ) const;

    private:
      std::optional<RoadLocation> nearestOnRoad( int road, double x, double y, bool blendReach = false ) const;

      std::vector<Road> mRoads;
      std::vector<std::vector<RoadMarkingLine>> mMarkings;
      std::vector<std::vector<double>> mCumulative; //!< per road: station of each vertex
      struct Segment
      {
        int road, index;
      };
      std::vector<Segment> mSegments;
      SpatialGrid mGrid;      //!< segments by their reach to the shoulder's outer edge
      SpatialGrid mBlendGrid; //!< segments by their reach to the end of the terrain blend
  };

} // namespace geostation

#endif // GEOSTATION_SIMULATION_ROADNETWORK_H
