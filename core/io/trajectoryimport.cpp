/***************************************************************************
  trajectoryimport.cpp - a mapping van's calibration plus trajectory as a block
 ***************************************************************************/
#include "io/trajectoryimport.h"

#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "geometry/crs.h"
#include "geometry/rotation.h"
#include "io/textfile.h"

namespace fs = std::filesystem;

namespace geostation
{
  namespace
  {
    std::string trim( const std::string &s )
    {
      const size_t a = s.find_first_not_of( " \t\r\n" );
      if ( a == std::string::npos )
        return {};
      return s.substr( a, s.find_last_not_of( " \t\r\n" ) - a + 1 );
    }

    //! One CSV record (RFC 4180 quotes; a quoted field may not span lines here).
    std::vector<std::string> splitCsv( const std::string &line )
    {
      std::vector<std::string> fields( 1 );
      bool quoted = false;
      for ( size_t i = 0; i < line.size(); ++i )
      {
        const char c = line[i];
        if ( quoted )
        {
          if ( c == '"' && i + 1 < line.size() && line[i + 1] == '"' )
            fields.back() += '"', ++i;
          else if ( c == '"' )
            quoted = false;
          else
            fields.back() += c;
        }
        else if ( c == '"' )
          quoted = true;
        else if ( c == ',' || c == ';' || c == '\t' )
          fields.emplace_back();
        else
          fields.back() += c;
      }
      for ( std::string &f : fields )
        f = trim( f );
      return fields;
    }

    struct Table
    {
      fs::path file;
      std::vector<std::string> header;
      std::vector<std::vector<std::string>> rows;

      std::optional<size_t> column( std::initializer_list<const char *> names ) const
      {
        for ( const char *name : names )
          for ( size_t i = 0; i < header.size(); ++i )
            if ( asciiLower( header[i] ) == name )
              return i;
        return std::nullopt;
      }

      double number( size_t row, size_t column ) const
      {
        const std::string &text = column < rows[row].size() ? rows[row][column] : std::string();
        char *end = nullptr;
        const double v = std::strtod( text.c_str(), &end );
        if ( text.empty() || *end != '\0' || !std::isfinite( v ) )
          throw std::invalid_argument( "the trajectory table " + file.string() + ", row " + std::to_string( row + 1 ) + ": \"" + header[column] + "\" is \"" + text + "\", not a number" );
        return v;
      }

      std::string text( size_t row, size_t column ) const { return column < rows[row].size() ? rows[row][column] : std::string(); }

      std::string headerList() const
      {
        std::string s;
        for ( const std::string &h : header )
          s += ( s.empty() ? "" : ", " ) + h;
        return s;
      }
    };

    Table readTable( const fs::path &file )
    {
      std::ifstream in( file );
      if ( !in )
        throw std::invalid_argument( "the trajectory table " + file.string() + " does not exist or cannot be read" );
      Table t;
      t.file = file;
      std::string line;
      while ( std::getline( in, line ) )
      {
        if ( trim( line ).empty() || trim( line )[0] == '#' )
          continue;
        if ( t.header.empty() )
          t.header = splitCsv( line );
        else
          t.rows.push_back( splitCsv( line ) );
      }
      if ( t.header.empty() || t.rows.empty() )
        throw std::invalid_argument( "the trajectory table " + file.string() + " has no rows" );
      return t;
    }

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

    void refuseRadiansAsDegrees( const Table &t, size_t roll, size_t pitch, size_t heading )
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

  BlockImportSummary importTrajectory( const std::vector<RigCamera> &rig, const fs::path &trajectoryCsv, const TrajectoryImportOptions &options )
  {
    if ( options.crs.empty() )
      throw std::invalid_argument( "give the CRS the block is to be in" );
    requireProjectedMetricCrs( options.crs );
    if ( rig.empty() )
      throw std::invalid_argument( "the calibration holds no camera" );
    const Table t = readTable( trajectoryCsv );
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
    std::vector<std::optional<size_t>> imageColumn;
    for ( const RigCamera &c : rig )
    {
      std::optional<size_t> column;
      for ( size_t i = 0; i < t.header.size(); ++i )
        if ( asciiLower( t.header[i] ) == asciiLower( "image_" + c.camera.id ) || ( rig.size() == 1 && asciiLower( t.header[i] ) == "image" ) )
          column = i;
      if ( !column && c.imagePattern.empty() )
        throw std::invalid_argument( "camera \"" + c.camera.id + "\" has no image names: give the table a column \"" + ( rig.size() == 1 ? std::string( "image" ) : "image_" + c.camera.id )
                                     + "\" or the camera an image_pattern" + have );
      imageColumn.push_back( column );
    }

    std::unique_ptr<CrsTransform> fromWgs84;
    if ( geographic )
      fromWgs84 = std::make_unique<CrsTransform>( "EPSG:4326", options.crs );
    const Convergence convergence( options.crs );

    BlockImportSummary import;
    import.format = "opencv-trajectory";
    Block &block = import.block;
    block.crs = options.crs;
    for ( const RigCamera &c : rig )
    {
      block.cameras.push_back( c.camera );
      import.converted.push_back( "camera \"" + c.camera.id + "\" from the OpenCV calibration (principal point + 0.5 px: OpenCV's pixel centres are integers), lever arm "
                                  + std::to_string( c.leverArmM.x() ) + ", " + std::to_string( c.leverArmM.y() ) + ", " + std::to_string( c.leverArmM.z() ) + " m" );
    }
    for ( size_t r = 0; r < t.rows.size(); ++r )
    {
      Station s;
      char fallback[32];
      std::snprintf( fallback, sizeof( fallback ), "S%04zu", r + 1 );
      s.id = station && !t.text( r, *station ).empty() ? t.text( r, *station ) : fallback;
      if ( block.findStation( s.id ) )
        throw std::invalid_argument( "the trajectory table, row " + std::to_string( r + 1 ) + ": station \"" + s.id + "\" is there twice" );
      s.time = time ? t.text( r, *time ) : std::string();
      Eigen::Vector3d position;
      if ( geographic )
      {
        position = fromWgs84->transform( { t.number( r, *lon ), t.number( r, *lat ), t.number( r, *z ) } );
        if ( !position.allFinite() )
          throw std::invalid_argument( "the trajectory table, row " + std::to_string( r + 1 ) + ": latitude/longitude cannot be brought into " + options.crs );
      }
      else
        position = { t.number( r, *x ), t.number( r, *y ), t.number( r, *z ) };
      const double gamma = convergence.degreesAt( position );
      block.stations.push_back( s );
      for ( size_t c = 0; c < rig.size(); ++c )
      {
        BlockImage image;
        image.cameraId = rig[c].camera.id;
        image.stationId = s.id;
        image.id = rig.size() == 1 ? s.id : s.id + "_" + rig[c].camera.id;
        image.path = imageColumn[c] ? t.text( r, *imageColumn[c] )
                                    : replaceAll( replaceAll( replaceAll( rig[c].imagePattern, "{station}", s.id ), "{row}", std::to_string( r + 1 ) ), "{time}", s.time );
        if ( image.path.empty() )
          throw std::invalid_argument( "the trajectory table, row " + std::to_string( r + 1 ) + ": no image name for camera \"" + rig[c].camera.id + "\"" );
        ExteriorOrientation eo;
        Eigen::Matrix3d worldFromCamera;
        if ( body )
        {
          const Eigen::Vector3d rph( t.number( r, *roll ) * toDeg, t.number( r, *pitch ) * toDeg, t.number( r, *heading ) * toDeg );
          eo.projectionCentre = position + worldFromBody( rph, gamma ) * rig[c].leverArmM;
          worldFromCamera = worldFromRigCamera( rph, rig[c], gamma );
        }
        else
        {
          eo.projectionCentre = position;
          worldFromCamera = worldFromCameraRotationDeg( t.number( r, *omega ) * toDeg, t.number( r, *phi ) * toDeg, t.number( r, *kappa ) * toDeg );
        }
        const Eigen::Vector3d opk = omegaPhiKappaDegFromRotation( worldFromCamera );
        eo.omegaDeg = opk.x();
        eo.phiDeg = opk.y();
        eo.kappaDeg = opk.z();
        image.exterior = eo;
        import.imageIdBySourceName[image.path] = image.id;
        block.images.push_back( image );
      }
    }
    import.converted.push_back( std::to_string( block.stations.size() ) + " trajectory row(s) became stations with " + std::to_string( block.images.size() ) + " image(s)" );
    if ( body )
      import.converted.push_back( convergence.available() ? "headings turned from true to grid north by the meridian convergence at each station"
                                                          : "the CRS has no geographic relation: headings are taken as grid headings" );

    const fs::path folder = options.imageFolder.empty() ? fs::absolute( trajectoryCsv ).parent_path() : fs::absolute( options.imageFolder );
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
