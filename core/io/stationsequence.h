/***************************************************************************
  stationsequence.h - the exposure stations of a block, in run order
  -------------------------------------------------------------------------
  The Multiview steps through a mobile-mapping run station by station. The
  order is the stations' time (ISO 8601 sorts as text), then their id;
  stations without images are left out. Each station knows its images and
  its position (the mean projection centre of its oriented images), so a
  station can be picked from the map or from typed coordinates.
 ***************************************************************************/
#ifndef GEOSTATION_IO_STATIONSEQUENCE_H
#define GEOSTATION_IO_STATIONSEQUENCE_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/block.h"

namespace geostation
{

  struct SequenceStation
  {
    std::string id;
    std::string time;
    std::string trajectory;
    std::vector<std::string> imageIds;              //!< in block order
    std::optional<Eigen::Vector3d> position;        //!< mean projection centre (block CRS); none if no image is oriented
  };

  class StationSequence
  {
    public:
      StationSequence() = default;
      /**
       * Images without a station form one pseudo-station each (id = the
       * image id), so any oriented photo can be shown.
       */
      explicit StationSequence( const Block &block );

      int size() const { return static_cast<int>( mStations.size() ); }
      bool empty() const { return mStations.empty(); }
      const SequenceStation &at( int index ) const { return mStations.at( index ); }
      const std::vector<SequenceStation> &stations() const { return mStations; }

      //! -1 if not found.
      int indexOf( const std::string &stationId ) const;

      //! The station whose time is nearest to an ISO 8601 time (compared as UTC seconds); -1 if no station has a time.
      int indexNearestTime( const std::string &isoTime ) const;

      //! A station id, or else the station nearest to an ISO 8601 time; -1 if neither matches.
      int indexOfIdOrTime( const std::string &idOrTime ) const;

      //! The station nearest to a map position (XY, block CRS); -1 if none has a position.
      int indexNearest( const Eigen::Vector2d &pointInWorld ) const;

      //! index + step, clamped to the run.
      int stepped( int index, int step ) const;

      //! Seconds since 1970 of an ISO 8601 UTC time ("2025-05-01T10:00:00.000Z"); nothing if it does not parse.
      static std::optional<double> secondsFromIsoTime( const std::string &isoTime );

    private:
      std::vector<SequenceStation> mStations;
  };

} // namespace geostation

#endif // GEOSTATION_IO_STATIONSEQUENCE_H
