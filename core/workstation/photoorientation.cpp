/***************************************************************************
  photoorientation.cpp - one photo oriented interactively from control points
 ***************************************************************************/
#include "workstation/photoorientation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <fstream>
#include <stdexcept>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "geometry/projection.h"
#include "geometry/rotation.h"
#include "identification/threepointpose.h"
#include "identification/markcandidates.h"
#include "io/block.h"
#include "io/textfile.h"

namespace geostation
{
  namespace
  {
    using Affine = Eigen::Matrix<double, 2, 3>;

    Eigen::Vector2d apply( const Affine &a, const Eigen::Vector2d &p ) { return a * p.homogeneous(); }

    Affine inverseAffine( const Affine &a )
    {
      const Eigen::Matrix2d inverse = a.leftCols<2>().inverse();
      Affine result;
      result.leftCols<2>() = inverse;
      result.col( 2 ) = -inverse * a.col( 2 );
      return result;
    }

    Affine identityAffine()
    {
      Affine a;
      a << 1, 0, 0, 0, 1, 0;
      return a;
    }
  } // namespace

  std::string controlRoleName( ControlRole role )
  {
    switch ( role )
    {
      case ControlRole::Control:
        return "control";
      case ControlRole::Check:
        return "check";
      case ControlRole::Off:
        return "off";
    }
    return "off";
  }

  std::optional<ControlRole> controlRoleFromName( const std::string &name )
  {
    for ( ControlRole role : { ControlRole::Control, ControlRole::Check, ControlRole::Off } )
      if ( controlRoleName( role ) == name )
        return role;
    return std::nullopt;
  }

  void PhotoOrientationOptions::check() const
  {
    if ( !( blunderThreshold > 0.0 ) )
      throw std::invalid_argument( "The blunder threshold must be positive." );
  }

  PhotoOrientationSummary orientPhoto( const Camera &camera, const std::optional<Affine> &nominalFromFile, const std::vector<PhotoControlPoint> &points,
                                       const PhotoOrientationOptions &options )
  {
    options.check();
    const Affine toNominal = nominalFromFile.value_or( identityAffine() );
    if ( std::abs( toNominal.leftCols<2>().determinant() ) < 1e-12 )
      throw std::invalid_argument( "The scan affine of the photo is singular." );
    const Affine toFile = inverseAffine( toNominal );

    PhotoOrientationSummary summary;
    std::set<std::string> ids;
    std::vector<ControlPoint> control;
    std::vector<ImagePoint> observations;
    for ( const PhotoControlPoint &p : points )
    {
      if ( p.pointId.empty() )
        throw std::invalid_argument( "A control point has no id." );
      if ( !ids.insert( p.pointId ).second )
        throw std::invalid_argument( "Control point " + p.pointId + " is in the list twice." );
      if ( !( p.sigmaPx > 0.0 ) )
        throw std::invalid_argument( "Control point " + p.pointId + " has a non-positive pixel sigma." );
      if ( !p.world.allFinite() || ( p.pixelInFile && !p.pixelInFile->allFinite() ) )
        throw std::invalid_argument( "Control point " + p.pointId + " has a coordinate that is not a number." );
      if ( p.role == ControlRole::Off || !p.pixelInFile )
        continue;
      control.push_back( { p.pointId, p.world, p.sigmaM, p.role == ControlRole::Check } );
      // a pixel's sigma in the nominal frame: scaled by the scan affine's mean scale
      const double scale = std::sqrt( std::abs( toNominal.leftCols<2>().determinant() ) );
      observations.push_back( { p.pointId, apply( toNominal, *p.pixelInFile ), p.sigmaPx * scale } );
      ( p.role == ControlRole::Check ? summary.measuredCheck : summary.measuredControl ) += 1;
    }

    const int freeCount = static_cast<int>( std::count( options.freeInterior.begin(), options.freeInterior.end(), true ) );
    // the six exterior parameters and the freed interior ones, with at least one redundant observation
    summary.neededControl = std::max( 4, ( 6 + freeCount + 1 + 1 ) / 2 );
    summary.points.resize( points.size() );
    for ( size_t i = 0; i < points.size(); ++i )
    {
      summary.points[i].pointId = points[i].pointId;
      summary.points[i].measured = points[i].pixelInFile.has_value();
    }
    if ( summary.measuredControl < summary.neededControl )
    {
      std::ostringstream m;
      m << "The resection needs " << summary.neededControl << " control points measured in the photo"
        << ( freeCount ? " for the freed camera parameters" : "" ) << "; " << summary.measuredControl << " so far.";
      summary.status = PhotoOrientationSummary::Status::NotEnoughPoints;
      summary.message = m.str();
      return summary;
    }

    ResectionOptions resection;
    resection.freeInterior = options.freeInterior;
    resection.blunderThreshold = options.blunderThreshold;
    // Baarda's data snooping: the worst point above the threshold is left out and the rest solved again, so one
    // blunder does not smear over every point; it stays in the list, flagged with its w, for the operator to decide
    resection.removeBlunders = true;
    summary.resection = resectImage( camera, control, observations, resection );
    if ( !summary.resection.ok() )
    {
      summary.status = PhotoOrientationSummary::Status::Failed;
      summary.message = summary.resection.message;
      return summary;
    }
    summary.status = PhotoOrientationSummary::Status::Oriented;

    std::map<std::string, const PointResidual *> residuals;
    for ( const PointResidual &r : summary.resection.residuals )
      residuals[r.pointId] = &r;
    const OrientedImage oriented( summary.resection.camera, summary.resection.exterior );
    const Eigen::Matrix2d linearToFile = toFile.leftCols<2>();
    int flagged = 0;
    for ( size_t i = 0; i < points.size(); ++i )
    {
      const PhotoControlPoint &p = points[i];
      PhotoControlResult &result = summary.points[i];
      const GroundProjection projection = oriented.projectGroundToPixel( p.world );
      if ( projection.ok() )
      {
        result.projectedInFile = apply( toFile, projection.pixelInImage );
        result.inFrame = projection.inFrame;
      }
      const auto r = residuals.find( p.pointId );
      if ( r == residuals.end() || p.role == ControlRole::Off )
        continue;
      result.residualPx = linearToFile * r->second->residualPx;
      result.normalised = r->second->normalised;
      result.blunder = r->second->blunder;
      if ( r->second->check || r->second->blunder )
        result.groundErrorM = r->second->groundErrorM;
      flagged += result.blunder ? 1 : 0;
    }
    std::ostringstream m;
    m.setf( std::ios::fixed );
    m.precision( 2 );
    m << "Oriented from " << summary.resection.controlCount << " control points: sigma0 " << summary.resection.sigma0 << ", RMSE "
      << summary.resection.rmseControlPx << " px";
    if ( summary.resection.checkCount > 0 )
      m << ", check points " << summary.resection.rmseCheckPx << " px (" << summary.resection.rmseCheckM << " m)";
    if ( flagged > 0 )
      m << "; " << flagged << ( flagged == 1 ? " point flagged as a blunder and left out" : " points flagged as blunders and left out" );
    m << ".";
    summary.message = m.str();
    return summary;
  }

  std::vector<ControlOffer> offerPredictedControl( const cv::Mat &greyFile, const Camera &camera, const std::optional<Affine> &nominalFromFile,
      const ExteriorOrientation &approximate, const std::vector<PhotoControlPoint> &points, const ControlPredictionOptions &options )
  {
    options.check();
    const Affine toNominal = nominalFromFile.value_or( identityAffine() );
    const Affine toFile = inverseAffine( toNominal );
    std::vector<ControlPoint> control;
    std::vector<ImagePoint> measured;
    for ( const PhotoControlPoint &p : points )
    {
      if ( p.role == ControlRole::Off )
        continue;
      control.push_back( { p.pointId, p.world, p.sigmaM, false } );
      if ( p.pixelInFile )
        measured.push_back( { p.pointId, apply( toNominal, *p.pixelInFile ), p.sigmaPx } );
    }
    const cv::Mat grey = nominalFromFile ? nominalImage( greyFile, camera, toNominal ) : greyFile;
    const ControlPredictionSummary prediction = predictAndFindControl( grey, camera, approximate, control, measured, options );
    std::vector<ControlOffer> offers;
    for ( const PredictedPoint &p : prediction.points )
      offers.push_back( { p.pointId, p.status, p.reason, apply( toFile, p.pixelInImage ), apply( toFile, p.predictedPx ) } );
    return offers;
  }

  std::vector<ExteriorOrientation> approximatePhotoOrientations( const Camera &camera, const std::optional<Affine> &nominalFromFile,
      const std::vector<PhotoControlPoint> &points, const std::optional<Eigen::Vector3d> &approximateCentre )
  {
    const Affine toNominal = nominalFromFile.value_or( identityAffine() );
    // the measured points as rays (ideal coordinates) and ground points
    std::vector<Eigen::Vector3d> world;
    std::vector<Eigen::Vector2d> ideal;
    for ( const PhotoControlPoint &p : points )
    {
      if ( p.role == ControlRole::Off )
        continue;
      if ( !p.pixelInFile )
        continue;
      if ( const std::optional<Eigen::Vector3d> ray = camera.rayInCameraFromPixel( apply( toNominal, *p.pixelInFile ) ) )
      {
        world.push_back( p.world );
        ideal.push_back( ray->head<2>() );
      }
    }
    if ( world.size() >= 3 )
    {
      // the three points spanning the largest triangle in the photo
      std::array<size_t, 3> best { 0, 1, 2 };
      double bestArea = -1.0;
      for ( size_t a = 0; a < ideal.size(); ++a )
        for ( size_t b = a + 1; b < ideal.size(); ++b )
          for ( size_t c = b + 1; c < ideal.size(); ++c )
          {
            const Eigen::Vector2d u = ideal[b] - ideal[a], v = ideal[c] - ideal[a];
            const double area = std::abs( u.x() * v.y() - u.y() * v.x() );
            if ( area > bestArea )
            {
              bestArea = area;
              best = { a, b, c };
            }
          }
      const Eigen::Vector3d origin = ( world[best[0]] + world[best[1]] + world[best[2]] ) / 3.0;
      const std::vector<ThreePointPose> poses = threePointPoses( { world[best[0]] - origin, world[best[1]] - origin, world[best[2]] - origin },
                                                                 { ideal[best[0]], ideal[best[1]], ideal[best[2]] } );
      std::vector<std::pair<double, ExteriorOrientation>> ranked;
      for ( const ThreePointPose &pose : poses )
      {
        const ExteriorOrientation eo = ExteriorOrientation::fromCentreAndRotation( pose.centre + origin, pose.cameraFromWorld.transpose() );
        const OrientedImage image( camera, eo );
        // how well the other measured points agree (ideal units); with three points all agree
        double misfit = 0.0;
        for ( size_t i = 0; i < world.size(); ++i )
        {
          const Eigen::Vector3d p = image.cameraFromWorld( world[i] );
          misfit += p.z() < 0.0 ? ( Eigen::Vector2d( -p.x() / p.z(), -p.y() / p.z() ) - ideal[i] ).squaredNorm() : 1e6;
        }
        ranked.emplace_back( misfit, eo );
      }
      std::stable_sort( ranked.begin(), ranked.end(), []( const auto &a, const auto &b ) { return a.first < b.first; } );
      std::vector<ExteriorOrientation> candidates;
      for ( const auto &[misfit, eo] : ranked )
        if ( world.size() == 3 || misfit < 1e-4 * static_cast<double>( world.size() ) )
          candidates.push_back( eo );
      return candidates;
    }
    if ( world.size() == 2 && approximateCentre && approximateCentre->allFinite() )
    {
      // Kabsch on the two rays and their cross product
      Eigen::Matrix3d fromCamera, toWorld;
      for ( int i = 0; i < 2; ++i )
      {
        fromCamera.col( i ) = Eigen::Vector3d( ideal[i].x(), ideal[i].y(), -1.0 ).normalized();
        toWorld.col( i ) = ( world[i] - *approximateCentre ).normalized();
      }
      fromCamera.col( 2 ) = fromCamera.col( 0 ).cross( fromCamera.col( 1 ) );
      toWorld.col( 2 ) = toWorld.col( 0 ).cross( toWorld.col( 1 ) );
      if ( fromCamera.col( 2 ).norm() < 1e-6 || toWorld.col( 2 ).norm() < 1e-6 )
        return {}; // the two points on one ray
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd( toWorld * fromCamera.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV );
      Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
      d( 2, 2 ) = ( svd.matrixU() * svd.matrixV().transpose() ).determinant() < 0.0 ? -1.0 : 1.0;
      return { ExteriorOrientation::fromCentreAndRotation( *approximateCentre, svd.matrixU() * d * svd.matrixV().transpose() ) };
    }
    return {};
  }

  std::vector<ControlOffer> offerPredictedControl( const cv::Mat &greyFile, const Camera &camera, const std::optional<Affine> &nominalFromFile,
      const std::vector<ExteriorOrientation> &candidates, const std::vector<PhotoControlPoint> &points, int *chosen, const ControlPredictionOptions &options )
  {
    std::vector<ControlOffer> best;
    int bestFound = -1;
    *chosen = -1;
    for ( size_t k = 0; k < candidates.size(); ++k )
    {
      std::vector<ControlOffer> offers = offerPredictedControl( greyFile, camera, nominalFromFile, candidates[k], points, options );
      const int found = static_cast<int>( std::count_if( offers.begin(), offers.end(), []( const ControlOffer &o ) { return o.status == PredictedPoint::Status::Found; } ) );
      if ( found > bestFound )
      {
        bestFound = found;
        best = std::move( offers );
        *chosen = static_cast<int>( k );
      }
    }
    return best;
  }

  std::optional<Eigen::Vector2d> refineMarkPixel( const cv::Mat &greyFile, const Eigen::Vector2d &clickedInFile, double searchRadiusPx,
      const MarkCandidateOptions &markOptions )
  {
    MarkCandidateOptions marks = markOptions;
    if ( greyFile.empty() || greyFile.type() != CV_8UC1 )
      throw std::invalid_argument( "Refining a mark needs an 8-bit grey image." );
    if ( !( searchRadiusPx > 0.0 ) || !clickedInFile.allFinite() )
      throw std::invalid_argument( "Refining a mark needs a finite pixel and a positive search radius." );
    // the window holds the search radius and a whole mark of the largest size around it (the photo's, not the window's)
    marks.maxDiameterPx = largestMarkPx( markOptions, greyFile.size() );
    const int half = static_cast<int>( std::ceil( searchRadiusPx + marks.maxDiameterPx ) );
    const cv::Rect wanted( static_cast<int>( std::floor( clickedInFile.x() ) ) - half, static_cast<int>( std::floor( clickedInFile.y() ) ) - half, 2 * half + 1,
                           2 * half + 1 );
    const cv::Rect window = wanted & cv::Rect( 0, 0, greyFile.cols, greyFile.rows );
    if ( window.width < 8 || window.height < 8 )
      return std::nullopt;
    const std::vector<MarkCandidate> found = detectMarkCandidates( greyFile( window ), marks );
    std::optional<Eigen::Vector2d> best;
    double bestDistance = searchRadiusPx;
    for ( const MarkCandidate &c : found )
    {
      const Eigen::Vector2d pixel = c.pixelInImage + Eigen::Vector2d( window.x, window.y );
      const double distance = ( pixel - clickedInFile ).norm();
      // the click is on the mark: a mark whose centre is further than its size from the click is another one
      if ( distance <= bestDistance && distance <= std::max( 3.0, c.diameterPx ) )
      {
        bestDistance = distance;
        best = pixel;
        if ( const std::optional<Eigen::Vector2d> centre = markCentre( greyFile, pixel, c.diameterPx, marks.brightMark ) )
          if ( ( *centre - pixel ).norm() < 0.5 * c.diameterPx )
            best = centre;
      }
    }
    return best;
  }

  void applyPhotoOrientation( Block &block, const std::string &imageId, const PhotoOrientationSummary &summary, const PhotoOrientationOptions &options )
  {
    if ( !summary.oriented() )
      throw std::invalid_argument( "The photo is not oriented: " + summary.message );
    auto image = std::find_if( block.images.begin(), block.images.end(), [&]( const BlockImage &i ) { return i.id == imageId; } );
    if ( image == block.images.end() )
      throw std::invalid_argument( "The block has no image " + imageId + "." );
    image->exterior = summary.resection.exterior;
    if ( std::any_of( options.freeInterior.begin(), options.freeInterior.end(), []( bool free ) { return free; } ) )
      for ( Camera &camera : block.cameras )
        if ( camera.id == image->cameraId )
        {
          Camera estimated = summary.resection.camera;
          estimated.id = camera.id;
          camera = estimated;
        }
  }

  namespace
  {
    //! One CSV line split into fields (double quotes around a field, "" inside one).
    std::vector<std::string> splitCsvLine( const std::string &line )
    {
      std::vector<std::string> fields( 1 );
      bool quoted = false;
      for ( size_t i = 0; i < line.size(); ++i )
      {
        const char c = line[i];
        if ( quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"' )
        {
          fields.back() += '"';
          ++i;
        }
        else if ( c == '"' )
          quoted = !quoted;
        else if ( c == ',' && !quoted )
          fields.emplace_back();
        else if ( c != '\r' )
          fields.back() += c;
      }
      return fields;
    }
  } // namespace

  void writePhotoControlTable( const std::filesystem::path &file, const std::string &imageId, const std::vector<PhotoControlPoint> &points )
  {
    std::ostringstream csv;
    csv.precision( 15 ); // millimetres of projected coordinates and 1e-6 px survive
    csv << "point_id,image_id,col,row,sigma_px,status,X,Y,Z,role\n";
    for ( const PhotoControlPoint &p : points )
    {
      csv << csvField( p.pointId ) << ',' << csvField( imageId ) << ',';
      if ( p.pixelInFile )
        csv << p.pixelInFile->x() << ',' << p.pixelInFile->y();
      else
        csv << ',';
      csv << ',' << p.sigmaPx << ',' << ( p.pixelInFile ? "reference" : "not_measured" ) << ',' << p.world.x() << ',' << p.world.y() << ',' << p.world.z() << ','
          << controlRoleName( p.role ) << '\n';
    }
    writeTextFileAtomically( file, csv.str(), "the control table" );
  }

  std::vector<PhotoControlPoint> readPhotoControlTable( const std::filesystem::path &file )
  {
    std::ifstream in( file );
    if ( !in )
      throw std::runtime_error( "Cannot read the control table " + file.string() + "." );
    std::string line;
    std::getline( in, line );
    const std::vector<std::string> header = splitCsvLine( line );
    std::map<std::string, size_t> column;
    for ( size_t i = 0; i < header.size(); ++i )
      column[header[i]] = i;
    for ( const char *name : { "point_id", "col", "row", "sigma_px", "X", "Y", "Z", "role" } )
      if ( !column.count( name ) )
        throw std::runtime_error( "The control table " + file.string() + " has no column " + name + "." );
    std::vector<PhotoControlPoint> points;
    int lineNumber = 1;
    while ( std::getline( in, line ) )
    {
      ++lineNumber;
      if ( line.empty() || line == "\r" )
        continue;
      const std::vector<std::string> f = splitCsvLine( line );
      auto bad = [&]( const std::string &what ) { return std::runtime_error( "Line " + std::to_string( lineNumber ) + " of the control table " + file.string() + ": " + what + "." ); };
      if ( f.size() != header.size() )
        throw bad( "it has " + std::to_string( f.size() ) + " fields, the header " + std::to_string( header.size() ) );
      auto number = [&]( const char *name ) {
        try
        {
          size_t used = 0;
          const double value = std::stod( f[column.at( name )], &used );
          if ( used == f[column.at( name )].size() && std::isfinite( value ) )
            return value;
        }
        catch ( const std::exception & )
        {
        }
        throw bad( std::string( name ) + " is not a number" );
      };
      PhotoControlPoint p;
      p.pointId = f[column.at( "point_id" )];
      if ( p.pointId.empty() )
        throw bad( "the point has no id" );
      p.world = Eigen::Vector3d( number( "X" ), number( "Y" ), number( "Z" ) );
      p.sigmaPx = number( "sigma_px" );
      if ( !f[column.at( "col" )].empty() || !f[column.at( "row" )].empty() )
        p.pixelInFile = Eigen::Vector2d( number( "col" ), number( "row" ) );
      const std::optional<ControlRole> role = controlRoleFromName( f[column.at( "role" )] );
      if ( !role )
        throw bad( "the role must be control, check or off" );
      p.role = *role;
      points.push_back( p );
    }
    return points;
  }

} // namespace geostation
