/***************************************************************************
  trajectoryimport.cpp - a mapping van's calibration plus trajectory as a block
 ***************************************************************************/
#include "io/trajectoryimport.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "geometry/crs.h"
#include "geometry/rotation.h"
#include "geometry/trajectoryinterpolation.h"
#include "io/internal/csvtable.h"
#include "io/textfile.h"

namespace fs = std::filesystem;

namespace geostation
{
  namespace
  {
    std::string replaceAll( std::string s, const std::string &what, const std::string &with )
    {
      for ( size_t p = s.find( what ); p != std::string::npos; p = s.find( what, p + with.size() ) )
        s.replace( p, what.size(), with );
      return s;
    }

    //! Grid north against true north at a point of the block CRS, from points 11 m either side along the meridian.
    class Convergence
    {
      public:
        explicit Convergence( const std::string &crs )
        {
          try
          {
            mToGeographic = std::make_unique<CrsTransform>( crs, "EPSG:4326" );
            mToGrid = std::make_unique<CrsTransform>( "EPSG:4326", crs );
          }
          catch ( const std::exception & )
          {
            mToGeographic.reset(); // a local engineering CRS: grid north is taken as true north
          }
        }

        bool available() const { return mToGeographic != nullptr; }

        double degreesAt( const Eigen::Vector3d &pointInGrid ) const
        {
          if ( !mToGeographic )
            return 0.0;
          const Eigen::Vector3d geo = mToGeographic->transform( pointInGrid );
          const Eigen::Vector3d north = mToGrid->transform( geo + Eigen::Vector3d( 0, 1e-4, 0 ) ) - mToGrid->transform( geo - Eigen::Vector3d( 0, 1e-4, 0 ) );
          if ( !north.allFinite() )
            return 0.0;
          return -radToDeg( std::atan2( north.x(), north.y() ) );
        }

      private:
        std::unique_ptr<CrsTransform> mToGeographic, mToGrid;
    };

    const Eigen::Matrix3d kEnuFromNed = ( Eigen::Matrix3d() << 0, 1, 0, 1, 0, 0, 0, 0, -1 ).finished();
    //! The forward camera: image right = body y, image up = body -z, looking along body x (camera z backwards).
    const Eigen::Matrix3d kBodyFromForwardCamera = ( Eigen::Matrix3d() << 0, 0, -1, 1, 0, 0, 0, -1, 0 ).finished();

    Eigen::Matrix3d rollPitchHeading( const Eigen::Vector3d &deg )
    {
      const double r = degToRad( deg.x() ), p = degToRad( deg.y() ), h = degToRad( deg.z() );
      const Eigen::Matrix3d rx = ( Eigen::Matrix3d() << 1, 0, 0, 0, std::cos( r ), -std::sin( r ), 0, std::sin( r ), std::cos( r ) ).finished();
      const Eigen::Matrix3d ry = ( Eigen::Matrix3d() << std::cos( p ), 0, std::sin( p ), 0, 1, 0, -std::sin( p ), 0, std::cos( p ) ).finished();
      const Eigen::Matrix3d rz = ( Eigen::Matrix3d() << std::cos( h ), -std::sin( h ), 0, std::sin( h ), std::cos( h ), 0, 0, 0, 1 ).finished();
      return rz * ry * rx;
    }

    void refuseRadiansAsDegrees( const CsvTable &t, size_t roll, size_t pitch, size_t heading )
    {
      if ( t.rows.size() < 10 )
        return;
      double maxAll = 0.0, maxRollPitch = 0.0, minHeading = 1e300, maxHeading = -1e300;
      for ( size_t r = 0; r < t.rows.size(); ++r )
      {
        const double a = t.number( r, roll ), b = t.number( r, pitch ), h = t.number( r, heading );
        maxAll = std::max( { maxAll, std::abs( a ), std::abs( b ), std::abs( h ) } );
        maxRollPitch = std::max( { maxRollPitch, std::abs( a ), std::abs( b ) } );
        minHeading = std::min( minHeading, h );
        maxHeading = std::max( maxHeading, h );
      }
      if ( maxAll <= 2.0 * kPi + 1e-9 && maxRollPitch <= 0.2 && maxHeading - minHeading > 0.5 )
        throw std::invalid_argument( "the angles of the trajectory table " + t.file.string() + " look like radians (every value within +-2 pi, roll and pitch within +-0.2, the heading turning by "
                                     + std::to_string( maxHeading - minHeading ) + "); they are read as degrees: say that they are radians" );
    }
  } // namespace

  Eigen::Matrix3d worldFromBody( const Eigen::Vector3d &rollPitchHeadingDeg, double convergenceDeg )
  {
    const double g = degToRad( convergenceDeg );
    const Eigen::Matrix3d gridFromEnu = ( Eigen::Matrix3d() << std::cos( g ), -std::sin( g ), 0, std::sin( g ), std::cos( g ), 0, 0, 0, 1 ).finished();
    return gridFromEnu * kEnuFromNed * rollPitchHeading( rollPitchHeadingDeg );
  }

  Eigen::Matrix3d worldFromRigCamera( const Eigen::Vector3d &rollPitchHeadingDeg, const RigCamera &camera, double convergenceDeg )
  {
    return worldFromBody( rollPitchHeadingDeg, convergenceDeg ) * rollPitchHeading( camera.boresightDeg ) * kBodyFromForwardCamera;
  }

  namespace
  {
    //! One station to be: where, how it was turned, and its images (one per rig camera).
    struct StationSource
    {
      std::string id, timeText;
      size_t row = 0; //!< 0-based row of the table that gives the station (the trajectory's, or the events')
      Eigen::Vector3d position = Eigen::Vector3d::Zero(); //!< block CRS
      std::optional<Eigen::Vector3d> rollPitchHeadingDeg;  //!< the body's attitude
      std::optional<Eigen::Matrix3d> worldFromCamera;      //!< or the one camera's own orientation
    };

    //! Roll, pitch, heading (degrees) of rollPitchHeading()'s rotation.
    Eigen::Vector3d rollPitchHeadingOf( const Eigen::Matrix3d &r )
    {
      return Eigen::Vector3d( radToDeg( std::atan2( r( 2, 1 ), r( 2, 2 ) ) ), radToDeg( -std::asin( std::clamp( r( 2, 0 ), -1.0, 1.0 ) ) ), radToDeg( std::atan2( r( 1, 0 ), r( 0, 0 ) ) ) );
    }

    //! Each camera's image column of the table (image, or image_<camera id>), or nothing where the camera has a pattern.
    std::vector<std::optional<size_t>> imageColumns( const CsvTable &t, const std::vector<RigCamera> &rig )
    {
      std::vector<std::optional<size_t>> columns;
      for ( const RigCamera &c : rig )
      {
        std::optional<size_t> column;
        for ( size_t i = 0; i < t.header.size(); ++i )
          if ( asciiLower( t.header[i] ) == asciiLower( "image_" + c.camera.id ) || ( rig.size() == 1 && asciiLower( t.header[i] ) == "image" ) )
            column = i;
        if ( !column && c.imagePattern.empty() )
          throw std::invalid_argument( "camera \"" + c.camera.id + "\" has no image names: give the table a column \"" + ( rig.size() == 1 ? std::string( "image" ) : "image_" + c.camera.id )
                                       + "\" or the camera an image_pattern (" + t.name + " has: " + t.headerList() + ")" );
        columns.push_back( column );
      }
      return columns;
    }

    std::string stationIdOf( const CsvTable &t, std::optional<size_t> column, size_t row, size_t number )
    {
      char fallback[32];
      std::snprintf( fallback, sizeof( fallback ), "S%04zu", number );
      return column && !t.text( row, *column ).empty() ? t.text( row, *column ) : std::string( fallback );
    }

    std::string seconds( double s )
    {
      char text[32];
      std::snprintf( text, sizeof( text ), "%.3g s", s );
      return text;
    }

    //! The events (exposure times) as stations, their poses interpolated in the trajectory's samples.
    std::vector<StationSource> interpolatedStations( const std::vector<StationSource> &samples, const CsvTable &trajectory, std::optional<size_t> trajectoryTime,
                                                     const CsvTable &events, const TrajectoryImportOptions &options, BlockImportSummary &import )
    {
      if ( !trajectoryTime )
        throw std::invalid_argument( "the trajectory table needs a time column (time, timestamp, gps_time) to interpolate the events at (it has: " + trajectory.headerList() + ")" );
      const std::optional<size_t> eventTime = events.column( { "time", "timestamp", "gps_time", "utc" } );
      if ( !eventTime )
        throw std::invalid_argument( "the events table needs a time column (time, timestamp, gps_time) on the trajectory's clock (it has: " + events.headerList() + ")" );
      const bool body = samples.front().rollPitchHeadingDeg.has_value();
      std::vector<TrajectoryPose> poses;
      for ( const StationSource &s : samples )
        poses.push_back( { trajectory.seconds( s.row, *trajectoryTime ), s.position, body ? rollPitchHeading( *s.rollPitchHeadingDeg ) : *s.worldFromCamera } );
      const TrajectoryInterpolator trajectoryAt = [&] {
        try
        {
          return TrajectoryInterpolator( std::move( poses ), options.maxTrajectoryGapS );
        }
        catch ( const std::invalid_argument &e )
        {
          throw std::invalid_argument( "the trajectory table " + trajectory.file.string() + ": " + e.what() );
        }
      }();
      const std::optional<size_t> station = events.column( { "station", "station_id", "id" } );
      std::vector<StationSource> out;
      int outside = 0, inGap = 0;
      for ( size_t r = 0; r < events.rows.size(); ++r )
      {
        const double t = events.seconds( r, *eventTime );
        const TrajectoryLookup at = trajectoryAt.at( t );
        if ( at.status != TrajectoryLookup::Status::Interpolated )
        {
          const bool gap = at.status == TrajectoryLookup::Status::InGap;
          ( gap ? inGap : outside ) += 1;
          if ( inGap + outside <= 10 )
            import.dropped.push_back( "event row " + std::to_string( r + 1 ) + " (time " + events.text( r, *eventTime ) + "): "
                                      + ( gap ? "the trajectory has a gap of " + seconds( at.gapS ) + " there (more than " + seconds( options.maxTrajectoryGapS ) + ")"
                                              : "outside the trajectory's time span" ) );
          continue;
        }
        StationSource s;
        s.row = r;
        s.id = stationIdOf( events, station, r, out.size() + 1 );
        s.timeText = events.text( r, *eventTime );
        s.position = at.pose.position;
        if ( body )
          s.rollPitchHeadingDeg = rollPitchHeadingOf( at.pose.attitude );
        else
          s.worldFromCamera = at.pose.attitude;
        out.push_back( s );
      }
      if ( inGap + outside > 10 )
        import.dropped.push_back( "... " + std::to_string( inGap + outside - 10 ) + " more event row(s) not interpolated" );
      char span[96];
      std::snprintf( span, sizeof( span ), "%.3f to %.3f s", trajectoryAt.startS(), trajectoryAt.endS() );
      if ( out.empty() )
        throw std::invalid_argument( "none of the " + std::to_string( events.rows.size() ) + " events of " + events.file.string() + " can be interpolated in the trajectory (" + span + ", gaps up to "
                                     + seconds( options.maxTrajectoryGapS ) + "): are both on the same clock?" );
      char rate[64];
      std::snprintf( rate, sizeof( rate ), "%.1f Hz", 1.0 / trajectoryAt.medianIntervalS() );
      import.converted.push_back( std::to_string( out.size() ) + " event(s) interpolated in the trajectory's " + std::to_string( samples.size() ) + " samples (" + span + ", " + rate
                                  + "): positions by cubic Hermite curves, attitudes by slerp" );
      if ( outside + inGap > 0 )
        import.warnings.push_back( std::to_string( outside ) + " event(s) outside the trajectory's time span and " + std::to_string( inGap ) + " in its gaps were left out" );
      return out;
    }
  } // namespace

  BlockImportSummary importTrajectory( const std::vector<RigCamera> &rig, const fs::path &trajectoryCsv, const TrajectoryImportOptions &options )
  {
    if ( options.crs.empty() )
      throw std::invalid_argument( "give the CRS the block is to be in" );
    requireProjectedMetricCrs( options.crs );
    if ( rig.empty() )
      throw std::invalid_argument( "the calibration holds no camera" );
    const CsvTable t = readCsvTable( trajectoryCsv, "the trajectory table" );
    const std::string have = " (the table has: " + t.headerList() + ")";

    // positions
    auto x = t.column( { "x", "easting", "east" } ), y = t.column( { "y", "northing", "north" } ), z = t.column( { "z", "height", "h", "alt", "altitude", "ellipsoidal_height" } );
    auto lat = t.column( { "latitude", "lat" } ), lon = t.column( { "longitude", "lon", "long" } );
    const bool geographic = lat && lon && z;
    if ( !geographic && !( x && y && z ) )
      throw std::invalid_argument( "the trajectory table has no position columns: expected X, Y, Z (block CRS) or latitude, longitude, height (WGS 84)" + have );
    // attitude
    auto roll = t.column( { "roll" } ), pitch = t.column( { "pitch" } ), heading = t.column( { "heading", "yaw" } );
    auto omega = t.column( { "omega" } ), phi = t.column( { "phi" } ), kappa = t.column( { "kappa" } );
    const bool body = roll && pitch && heading;
    if ( !body && !( omega && phi && kappa ) )
      throw std::invalid_argument( "the trajectory table has no attitude columns: expected roll, pitch, heading (the vehicle's) or omega, phi, kappa (the camera's)" + have );
    if ( !body )
    {
      if ( rig.size() != 1 )
        throw std::invalid_argument( "omega, phi, kappa are one camera's orientation, but the calibration has " + std::to_string( rig.size() ) + " cameras: give roll, pitch, heading" );
      if ( rig.front().leverArmM != Eigen::Vector3d::Zero() || rig.front().boresightDeg != Eigen::Vector3d::Zero() )
        throw std::invalid_argument( "omega, phi, kappa are the camera's own orientation: a lever arm or boresight applies to roll, pitch, heading" );
    }
    const double toDeg = options.anglesInRadians ? 180.0 / kPi : 1.0;
    if ( body && !options.anglesInRadians )
      refuseRadiansAsDegrees( t, *roll, *pitch, *heading );
    auto time = t.column( { "time", "timestamp", "gps_time", "utc" } ), station = t.column( { "station", "station_id", "id" } );

    std::unique_ptr<CrsTransform> fromWgs84;
    if ( geographic )
      fromWgs84 = std::make_unique<CrsTransform>( "EPSG:4979", options.crs ); // GNSS heights are ellipsoidal
    const Convergence convergence( options.crs );

    // the trajectory's rows: the stations, or the samples the events are interpolated in
    std::vector<StationSource> rows;
    for ( size_t r = 0; r < t.rows.size(); ++r )
    {
      StationSource s;
      s.row = r;
      s.id = stationIdOf( t, station, r, r + 1 );
      s.timeText = time ? t.text( r, *time ) : std::string();
      if ( geographic )
      {
        s.position = fromWgs84->transform( { t.number( r, *lon ), t.number( r, *lat ), t.number( r, *z ) } );
        if ( !s.position.allFinite() )
          throw std::invalid_argument( "the trajectory table, row " + std::to_string( r + 1 ) + ": latitude/longitude cannot be brought into " + options.crs );
      }
      else
        s.position = { t.number( r, *x ), t.number( r, *y ), t.number( r, *z ) };
      if ( body )
        s.rollPitchHeadingDeg = Eigen::Vector3d( t.number( r, *roll ) * toDeg, t.number( r, *pitch ) * toDeg, t.number( r, *heading ) * toDeg );
      else
        s.worldFromCamera = worldFromCameraRotationDeg( t.number( r, *omega ) * toDeg, t.number( r, *phi ) * toDeg, t.number( r, *kappa ) * toDeg );
      rows.push_back( s );
    }

    BlockImportSummary import;
    import.format = "opencv-trajectory";
    std::optional<CsvTable> events;
    if ( !options.eventsCsv.empty() )
      events = readCsvTable( options.eventsCsv, "the events table" );
    const CsvTable &namesTable = events ? *events : t;
    const std::vector<std::optional<size_t>> imageColumn = imageColumns( namesTable, rig );
    const std::vector<StationSource> stations = events ? interpolatedStations( rows, t, time, *events, options, import ) : rows;

    Block &block = import.block;
    block.crs = options.crs;
    for ( const RigCamera &c : rig )
    {
      block.cameras.push_back( c.camera );
      import.converted.push_back( "camera \"" + c.camera.id + "\" from the OpenCV calibration (principal point + 0.5 px: OpenCV's pixel centres are integers), lever arm "
                                  + std::to_string( c.leverArmM.x() ) + ", " + std::to_string( c.leverArmM.y() ) + ", " + std::to_string( c.leverArmM.z() ) + " m" );
    }
    const std::string rowName = events ? "the events table" : "the trajectory table";
    for ( const StationSource &source : stations )
    {
      Station s;
      s.id = source.id;
      if ( block.findStation( s.id ) )
        throw std::invalid_argument( rowName + ", row " + std::to_string( source.row + 1 ) + ": station \"" + s.id + "\" is there twice" );
      s.time = source.timeText;
      const double gamma = convergence.degreesAt( source.position );
      block.stations.push_back( s );
      for ( size_t c = 0; c < rig.size(); ++c )
      {
        BlockImage image;
        image.cameraId = rig[c].camera.id;
        image.stationId = s.id;
        image.id = rig.size() == 1 ? s.id : s.id + "_" + rig[c].camera.id;
        image.path = imageColumn[c] ? namesTable.text( source.row, *imageColumn[c] )
                                    : replaceAll( replaceAll( replaceAll( rig[c].imagePattern, "{station}", s.id ), "{row}", std::to_string( source.row + 1 ) ), "{time}", s.time );
        if ( image.path.empty() )
          throw std::invalid_argument( rowName + ", row " + std::to_string( source.row + 1 ) + ": no image name for camera \"" + rig[c].camera.id + "\"" );
        if ( source.rollPitchHeadingDeg )
          image.exterior = ExteriorOrientation::fromCentreAndRotation( source.position + worldFromBody( *source.rollPitchHeadingDeg, gamma ) * rig[c].leverArmM,
                                                                       worldFromRigCamera( *source.rollPitchHeadingDeg, rig[c], gamma ) );
        else
          image.exterior = ExteriorOrientation::fromCentreAndRotation( source.position, *source.worldFromCamera );
        import.imageIdBySourceName[image.path] = image.id;
        block.images.push_back( image );
      }
    }
    if ( !events )
      import.converted.push_back( std::to_string( block.stations.size() ) + " trajectory row(s) became stations with " + std::to_string( block.images.size() ) + " image(s)" );
    else
      import.converted.push_back( std::to_string( block.stations.size() ) + " event(s) became stations with " + std::to_string( block.images.size() ) + " image(s)" );
    if ( geographic )
    {
      const std::string vertical = verticalCrsName( options.crs );
      import.converted.push_back( vertical.empty() ? "heights kept as given: ellipsoidal heights above WGS 84 (give a CRS with a vertical datum, e.g. EPSG:32617+5773, for heights above the geoid)"
                                                   : "ellipsoidal heights above WGS 84 became " + vertical + "s through its geoid model" );
    }
    if ( body )
      import.converted.push_back( convergence.available() ? "headings turned from true to grid north by the meridian convergence at each station"
                                                          : "the CRS has no geographic relation: headings are taken as grid headings" );

    const fs::path folder = options.imageFolder.empty() ? fs::absolute( events ? options.eventsCsv : trajectoryCsv ).parent_path() : fs::absolute( options.imageFolder );
    block.sourceFile = folder / "trajectory-import.geostation.json";
    if ( options.requireImageFiles )
      for ( const BlockImage &image : block.images )
      {
        try
        {
          requireReadableImageFile( block, image );
        }
        catch ( const std::runtime_error &e )
        {
          throw std::invalid_argument( std::string( e.what() ) + " (image names resolve in " + folder.string() + ")" );
        }
      }
    return import;
  }

} // namespace geostation
