/***************************************************************************
  metashapeimport.cpp - Metashape's camera XML as a GeoStation block
 ***************************************************************************/
#include "io/metashapeimport.h"

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include <cpl_error.h>
#include <cpl_minixml.h>
#include <Eigen/SVD>

#include "geometry/crs.h"
#include "io/colmapconversion.h"
#include "geometry/rotation.h"

namespace fs = std::filesystem;

namespace geostation
{
  namespace
  {
    using XmlPtr = std::unique_ptr<CPLXMLNode, decltype( &CPLDestroyXMLNode )>;

    XmlPtr parse( const fs::path &file )
    {
      CPLPushErrorHandler( CPLQuietErrorHandler );
      CPLXMLNode *root = CPLParseXMLFile( file.string().c_str() );
      CPLPopErrorHandler();
      return XmlPtr( root, CPLDestroyXMLNode );
    }

    std::vector<double> numbers( const char *text, const fs::path &file, const std::string &what )
    {
      std::vector<double> values;
      std::istringstream in( text ? text : "" );
      double v;
      while ( in >> v )
        values.push_back( v );
      if ( !in.eof() )
        throw std::invalid_argument( "the Metashape file " + file.string() + ": " + what + " holds something that is not a number" );
      return values;
    }

    double value( const CPLXMLNode *node, const char *name, const fs::path &file )
    {
      const char *text = CPLGetXMLValue( node, name, nullptr );
      if ( !text )
        return 0.0;
      const std::vector<double> v = numbers( text, file, std::string( "<" ) + name + ">" );
      if ( v.size() != 1 || !std::isfinite( v[0] ) )
        throw std::invalid_argument( "the Metashape file " + file.string() + ": <" + name + "> is not one number" );
      return v[0];
    }

    //! Throws unless the matrix is a rotation (orthonormal, determinant +1) to 1e-6: a singular or mirrored one would give no angles.
    void requireRotation( const Eigen::Matrix3d &rotation, const fs::path &file, const std::string &what )
    {
      if ( !rotation.allFinite() || ( rotation.transpose() * rotation - Eigen::Matrix3d::Identity() ).cwiseAbs().maxCoeff() > 1e-6 || rotation.determinant() < 0.0 )
        throw std::invalid_argument( "the Metashape file " + file.string() + ": " + what + " is not a rotation (orthonormal, not mirrored)" );
    }

    void forEachElement( const CPLXMLNode *node, const char *name, const std::function<void( const CPLXMLNode * )> &visit )
    {
      for ( const CPLXMLNode *child = node ? node->psChild : nullptr; child; child = child->psNext )
        if ( child->eType == CXT_Element )
        {
          if ( EQUAL( child->pszValue, name ) )
            visit( child );
          else if ( EQUAL( child->pszValue, "group" ) )
            forEachElement( child, name, visit ); // camera groups (folders)
        }
    }

    //! A required number in an attribute (or element) of a node.
    double requiredValue( const CPLXMLNode *node, const char *name, const fs::path &file, const std::string &what )
    {
      if ( !CPLGetXMLValue( node, name, nullptr ) )
        throw std::invalid_argument( "the Metashape file " + file.string() + ": " + what + " has no " + name );
      return value( node, name, file );
    }

    bool isFalse( const char *text ) { return text && ( EQUAL( text, "false" ) || EQUAL( text, "0" ) ); }

    /**
     * Metashape's markers: each with a reference becomes a control point, a check point where its
     * reference is not enabled, brought from the chunk's reference CRS into the block CRS (taken as
     * it is for a local chunk); its projections in the imported cameras that the operator placed
     * (pinned) become its observations. Metashape's own projections of a marker (not pinned) are
     * estimates, not measurements, and are left out.
     */
    void importMarkers( const CPLXMLNode *chunk, const fs::path &file, const std::string &reference, bool camerasInCrs, const std::string &crs,
                        const std::map<std::string, std::string> &labelOfCamera, BlockImportSummary &import )
    {
      const CPLXMLNode *markers = CPLGetXMLNode( const_cast<CPLXMLNode *>( chunk ), "markers" );
      if ( !markers )
        return;
      std::map<std::string, std::vector<ImportedObservation>> observed;
      int unpinned = 0;
      forEachElement( CPLGetXMLNode( const_cast<CPLXMLNode *>( chunk ), "frames" ), "frame", [&]( const CPLXMLNode *frame ) {
        forEachElement( CPLGetXMLNode( const_cast<CPLXMLNode *>( frame ), "markers" ), "marker", [&]( const CPLXMLNode *marker ) {
          const std::string markerId = CPLGetXMLValue( marker, "marker_id", "" );
          forEachElement( marker, "location", [&]( const CPLXMLNode *location ) {
            const auto camera = labelOfCamera.find( CPLGetXMLValue( location, "camera_id", "" ) );
            if ( camera == labelOfCamera.end() )
              return;
            if ( isFalse( CPLGetXMLValue( location, "pinned", nullptr ) ) )
            {
              ++unpinned;
              return;
            }
            const std::string what = "a location of marker " + markerId;
            ImportedObservation o;
            o.imageId = camera->second;
            o.pixelInImage = Eigen::Vector2d( requiredValue( location, "x", file, what ), requiredValue( location, "y", file, what ) );
            observed[markerId].push_back( o );
          } );
        } );
      } );
      const bool local = reference.empty() || reference.rfind( "LOCAL_CS", 0 ) == 0;
      std::unique_ptr<CrsTransform> toCrs;
      try
      {
        if ( !local )
          toCrs = std::make_unique<CrsTransform>( reference, crs );
      }
      catch ( const std::invalid_argument &e )
      {
        throw std::invalid_argument( "the Metashape file " + file.string() + ": the markers' reference CRS cannot be brought into " + crs + ": " + e.what() );
      }
      std::set<std::string> labels;
      int controls = 0, checks = 0, withoutReference = 0, unobserved = 0;
      forEachElement( markers, "marker", [&]( const CPLXMLNode *marker ) {
        const std::string id = CPLGetXMLValue( marker, "id", "" ), label = CPLGetXMLValue( marker, "label", id.c_str() );
        const CPLXMLNode *ref = CPLGetXMLNode( const_cast<CPLXMLNode *>( marker ), "reference" );
        if ( !ref || !CPLGetXMLValue( ref, "x", nullptr ) || !CPLGetXMLValue( ref, "y", nullptr ) || !CPLGetXMLValue( ref, "z", nullptr ) )
        {
          ++withoutReference;
          return;
        }
        if ( !labels.insert( label ).second )
          throw std::invalid_argument( "the Metashape file " + file.string() + " has the marker label \"" + label + "\" twice" );
        ImportedControlPoint point;
        point.pointId = label;
        point.world = Eigen::Vector3d( value( ref, "x", file ), value( ref, "y", file ), value( ref, "z", file ) );
        if ( toCrs )
        {
          point.world = toCrs->transform( point.world );
          if ( !point.world.allFinite() )
            throw std::invalid_argument( "marker \"" + label + "\" cannot be brought into " + crs );
        }
        if ( CPLGetXMLValue( ref, "sx", nullptr ) && CPLGetXMLValue( ref, "sy", nullptr ) && CPLGetXMLValue( ref, "sz", nullptr ) )
          point.sigmaM = Eigen::Vector3d( value( ref, "sx", file ), value( ref, "sy", file ), value( ref, "sz", file ) );
        point.check = isFalse( CPLGetXMLValue( ref, "enabled", nullptr ) );
        ++( point.check ? checks : controls );
        const auto seen = observed.find( id );
        if ( seen == observed.end() )
          ++unobserved;
        else
          for ( ImportedObservation o : seen->second )
          {
            o.pointId = label;
            import.observations.push_back( o );
          }
        import.controlPoints.push_back( point );
      } );
      if ( controls + checks > 0 )
        import.converted.push_back( std::to_string( controls ) + " marker(s) became control points and " + std::to_string( checks ) + " (reference not enabled) check points"
                                    + ( local ? std::string( ", their references as they are" ) : ", their references brought into " + crs ) + ", measured where pinned" );
      if ( withoutReference > 0 )
        import.dropped.push_back( std::to_string( withoutReference ) + " marker(s) without reference coordinates were left out" );
      if ( unpinned > 0 )
        import.dropped.push_back( std::to_string( unpinned ) + " marker projection(s) not pinned (Metashape's estimates, not measurements) were left out" );
      if ( unobserved > 0 )
        import.warnings.push_back( std::to_string( unobserved ) + " marker(s) are measured in no imported image" );
      if ( controls + checks > 0 && !local && !camerasInCrs )
        import.warnings.push_back( "the markers are in " + crs + ", but the cameras in the chunk's internal frame (the chunk has no transform): orient the block on the markers before using both" );
    }

    //! A Metashape sensor as GeoStation's camera, or the sentence why not.
    struct CameraFromSensor
    {
      CameraConversionStatus status = CameraConversionStatus::Converted;
      std::string message; //!< one sentence naming the sensor and what it lacks, or has that GeoStation's cameras do not
      Camera camera;       //!< when Converted

      bool ok() const { return status == CameraConversionStatus::Converted; }
    };

    /**
     * The camera of a frame sensor: Malformed without a calibration, an
     * image size or a positive focal length; NotRepresentable for another
     * type of sensor, k4, p3, p4 or the skew b2.
     */
    CameraFromSensor cameraFromSensor( const CPLXMLNode *sensor, const std::string &id, const fs::path &file )
    {
      CameraFromSensor result;
      const auto fail = [&result]( CameraConversionStatus status, std::string message ) {
        result.status = status;
        result.message = std::move( message );
        return result;
      };
      const std::string label = CPLGetXMLValue( sensor, "label", id.c_str() );
      const std::string type = CPLGetXMLValue( sensor, "type", "frame" );
      const std::string name = "Metashape sensor " + id + " (" + label + ")";
      if ( !EQUAL( type.c_str(), "frame" ) )
        return fail( CameraConversionStatus::NotRepresentable, name + " is a " + type + " sensor, which GeoStation's frame cameras cannot represent" );
      const CPLXMLNode *calibration = nullptr;
      forEachElement( sensor, "calibration", [&]( const CPLXMLNode *c ) {
        if ( !calibration || EQUAL( CPLGetXMLValue( c, "class", "" ), "adjusted" ) )
          calibration = c;
      } );
      if ( !calibration )
        return fail( CameraConversionStatus::Malformed, name + " has no calibration" );
      const CPLXMLNode *resolution = CPLGetXMLNode( const_cast<CPLXMLNode *>( calibration ), "resolution" );
      if ( !resolution )
        resolution = CPLGetXMLNode( const_cast<CPLXMLNode *>( sensor ), "resolution" );
      const int width = resolution ? std::atoi( CPLGetXMLValue( resolution, "width", "0" ) ) : 0;
      const int height = resolution ? std::atoi( CPLGetXMLValue( resolution, "height", "0" ) ) : 0;
      if ( width <= 0 || height <= 0 )
        return fail( CameraConversionStatus::Malformed, name + " has no image size (<resolution width height>)" );
      const double f = value( calibration, "f", file ), b1 = value( calibration, "b1", file ), b2 = value( calibration, "b2", file );
      for ( const char *term : { "k4", "p3", "p4" } )
        if ( value( calibration, term, file ) != 0.0 )
          return fail( CameraConversionStatus::NotRepresentable, name + " uses " + term + ", which GeoStation's lens models cannot represent exactly" );
      if ( b2 != 0.0 )
        return fail( CameraConversionStatus::NotRepresentable, name + " has the skew b2, which GeoStation's cameras cannot represent" );
      if ( !( f > 0.0 ) || !( f + b1 > 0.0 ) )
        return fail( CameraConversionStatus::Malformed, name + " has a focal length that is not positive" );
      Camera &camera = result.camera;
      camera.id = label.empty() ? "sensor" + id : label;
      camera.width = width;
      camera.height = height;
      camera.f = f + b1;
      camera.aspect = f / ( f + b1 );
      camera.cx = 0.5 * width + value( calibration, "cx", file );
      camera.cy = 0.5 * height + value( calibration, "cy", file );
      // Metashape's P1 is OpenCV's p2 and its P2 OpenCV's p1
      camera.distortion.coeffs = { value( calibration, "k1", file ), value( calibration, "k2", file ), value( calibration, "p2", file ),
                                   value( calibration, "p1", file ), value( calibration, "k3", file ) };
      camera.distortion.model = DistortionModel::OpenCV;
      return result;
    }

    //! The rotation part of the block CRS's derivative with respect to geocentric coordinates at a point.
    Eigen::Matrix3d crsFromGeocentricRotation( const CrsTransform &toCrs, const Eigen::Vector3d &geocentric )
    {
      Eigen::Matrix3d jacobian;
      const double h = 10.0;
      for ( int i = 0; i < 3; ++i )
      {
        Eigen::Vector3d step = Eigen::Vector3d::Zero();
        step[i] = h;
        jacobian.col( i ) = ( toCrs.transform( geocentric + step ) - toCrs.transform( geocentric - step ) ) / ( 2.0 * h );
      }
      // a conformal projection scales east and north alike: the polar factor is the rotation
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd( jacobian, Eigen::ComputeFullU | Eigen::ComputeFullV );
      return svd.matrixU() * svd.matrixV().transpose();
    }

    fs::path findImage( const fs::path &folder, const std::string &label )
    {
      std::error_code ec;
      if ( fs::exists( folder / label, ec ) && fs::is_regular_file( folder / label, ec ) )
        return label;
      for ( const char *ext : { ".jpg", ".JPG", ".jpeg", ".JPEG", ".tif", ".TIF", ".tiff", ".TIFF", ".png", ".PNG" } )
        if ( fs::exists( folder / ( label + ext ), ec ) )
          return label + ext;
      return {};
    }

    const Eigen::Matrix3d kFlipYZ = Eigen::Vector3d( 1.0, -1.0, -1.0 ).asDiagonal();
  } // namespace

  bool isMetashapeCameras( const fs::path &file )
  {
    std::error_code ec;
    if ( !fs::is_regular_file( file, ec ) )
      return false;
    const XmlPtr root = parse( file );
    const CPLXMLNode *chunk = root ? CPLSearchXMLNode( root.get(), "=chunk" ) : nullptr;
    return chunk && ( CPLGetXMLNode( const_cast<CPLXMLNode *>( chunk ), "sensors" ) || CPLGetXMLNode( const_cast<CPLXMLNode *>( chunk ), "cameras" ) );
  }

  BlockImportSummary importMetashapeCameras( const fs::path &xmlFile, const MetashapeImportOptions &options )
  {
    if ( options.crs.empty() )
      throw std::invalid_argument( "give the CRS the block is to be in" );
    requireProjectedMetricCrs( options.crs );
    std::error_code ec;
    if ( !fs::is_regular_file( xmlFile, ec ) )
      throw std::invalid_argument( "the Metashape file " + xmlFile.string() + " does not exist" );
    const XmlPtr root = parse( xmlFile );
    if ( !root )
      throw std::invalid_argument( "the Metashape file " + xmlFile.string() + " is not well-formed XML" );
    CPLXMLNode *chunk = CPLSearchXMLNode( root.get(), "=chunk" );
    if ( !chunk )
      throw std::invalid_argument( "the file " + xmlFile.string() + " is not Metashape's camera XML: it has no <chunk>" );

    BlockImportSummary import;
    import.format = "metashape";
    Block &block = import.block;
    block.crs = options.crs;

    std::map<std::string, std::string> cameraIdOfSensor, droppedSensor;
    forEachElement( CPLGetXMLNode( chunk, "sensors" ), "sensor", [&]( const CPLXMLNode *sensor ) {
      const std::string id = CPLGetXMLValue( sensor, "id", "" );
      CameraFromSensor converted = cameraFromSensor( sensor, id, xmlFile );
      if ( !converted.ok() )
      {
        droppedSensor[id] = converted.message;
        import.dropped.push_back( converted.message + "; its images were dropped" );
        return;
      }
      Camera &camera = converted.camera;
      if ( block.findCamera( camera.id ) )
        camera.id += "_" + id;
      cameraIdOfSensor[id] = camera.id;
      import.converted.push_back( "Metashape sensor " + id + " became camera \"" + camera.id + "\" (lens model opencv; Metashape's P1, P2 are OpenCV's p2, p1)" );
      block.cameras.push_back( camera );
    } );

    // the chunk's frame: internal -> geocentric (referenced) or -> local
    Eigen::Matrix3d chunkRotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d chunkTranslation = Eigen::Vector3d::Zero();
    double chunkScale = 1.0;
    const CPLXMLNode *chunkTransform = CPLGetXMLNode( chunk, "transform" );
    if ( chunkTransform )
    {
      const std::vector<double> r = numbers( CPLGetXMLValue( chunkTransform, "rotation", "1 0 0 0 1 0 0 0 1" ), xmlFile, "the chunk's <rotation>" );
      const std::vector<double> t = numbers( CPLGetXMLValue( chunkTransform, "translation", "0 0 0" ), xmlFile, "the chunk's <translation>" );
      if ( r.size() != 9 || t.size() != 3 )
        throw std::invalid_argument( "the Metashape file " + xmlFile.string() + ": the chunk's <transform> needs 9 rotation and 3 translation values" );
      chunkRotation = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>( r.data() );
      requireRotation( chunkRotation, xmlFile, "the chunk's <rotation>" );
      if ( !std::isfinite( t[0] ) || !std::isfinite( t[1] ) || !std::isfinite( t[2] ) )
        throw std::invalid_argument( "the Metashape file " + xmlFile.string() + ": the chunk's <translation> is not three numbers" );
      chunkTranslation = Eigen::Vector3d( t[0], t[1], t[2] );
      if ( CPLGetXMLValue( chunkTransform, "scale", nullptr ) )
        chunkScale = value( chunkTransform, "scale", xmlFile );
      if ( !( chunkScale > 0.0 ) )
        throw std::invalid_argument( "the Metashape file " + xmlFile.string() + ": the chunk's <scale> is not positive" );
    }
    const std::string reference = CPLGetXMLValue( chunk, "reference", "" );
    const bool geocentric = chunkTransform && !reference.empty() && reference.rfind( "LOCAL_CS", 0 ) != 0;
    std::unique_ptr<CrsTransform> toCrs;
    if ( geocentric )
    {
      toCrs = std::make_unique<CrsTransform>( "EPSG:4978", options.crs );
      import.converted.push_back( "the chunk is referenced: cameras brought from geocentric coordinates into " + options.crs );
    }
    else
      import.converted.push_back( chunkTransform ? "the chunk's transform (no geographic reference) gives the block coordinates as they are"
                                                 : "the chunk is not referenced: its internal coordinates are taken as they are" );

    const fs::path imageFolder = options.imageFolder.empty() ? fs::absolute( xmlFile ).parent_path() : fs::absolute( options.imageFolder );
    int unaligned = 0;
    std::map<std::string, std::string> labelOfCamera; // Metashape's camera id -> image id
    forEachElement( CPLGetXMLNode( chunk, "cameras" ), "camera", [&]( const CPLXMLNode *node ) {
      const std::string label = CPLGetXMLValue( node, "label", CPLGetXMLValue( node, "id", "" ) );
      const std::string sensorId = CPLGetXMLValue( node, "sensor_id", "" );
      if ( droppedSensor.count( sensorId ) )
        return;
      if ( !cameraIdOfSensor.count( sensorId ) )
        throw std::invalid_argument( "the Metashape file " + xmlFile.string() + ": camera \"" + label + "\" names sensor " + sensorId + ", which the file does not have" );
      const char *transformText = CPLGetXMLValue( node, "transform", nullptr );
      if ( !transformText )
      {
        ++unaligned;
        return;
      }
      const std::vector<double> m = numbers( transformText, xmlFile, "the <transform> of camera \"" + label + "\"" );
      if ( m.size() != 16 )
        throw std::invalid_argument( "the Metashape file " + xmlFile.string() + ": the <transform> of camera \"" + label + "\" needs 16 values" );
      const Eigen::Matrix4d chunkFromCamera = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>( m.data() );
      Eigen::Matrix3d rotation = chunkFromCamera.topLeftCorner<3, 3>();
      rotation.colwise().normalize(); // a rigid transform; normalised against rounding in the file
      requireRotation( rotation, xmlFile, "the <transform> of camera \"" + label + "\"" );
      if ( !chunkFromCamera.topRightCorner<3, 1>().allFinite() )
        throw std::invalid_argument( "the Metashape file " + xmlFile.string() + ": the <transform> of camera \"" + label + "\" has a position that is not three numbers" );
      Eigen::Vector3d centre = chunkScale * ( chunkRotation * chunkFromCamera.topRightCorner<3, 1>() ) + chunkTranslation;
      rotation = chunkRotation * rotation; // camera (x right, y down, z forward) to geocentric or local
      if ( geocentric )
      {
        rotation = crsFromGeocentricRotation( *toCrs, centre ) * rotation;
        centre = toCrs->transform( centre );
        if ( !centre.allFinite() )
          throw std::invalid_argument( "camera \"" + label + "\" cannot be brought into " + options.crs );
      }
      BlockImage image;
      image.id = label;
      if ( block.findImage( image.id ) )
        throw std::invalid_argument( "the Metashape file " + xmlFile.string() + " has the camera label \"" + label + "\" twice" );
      image.cameraId = cameraIdOfSensor.at( sensorId );
      image.stationId = label;
      const fs::path found = findImage( imageFolder, label );
      if ( found.empty() && options.requireImageFiles )
        throw std::invalid_argument( "the image of camera \"" + label + "\" is not in " + imageFolder.string() + " (looked for the label with .jpg, .tif and .png); give the image folder" );
      image.path = found.empty() ? label : found.generic_string();
      image.exterior = ExteriorOrientation::fromCentreAndRotation( centre, rotation * kFlipYZ );
      Station station;
      station.id = label;
      block.stations.push_back( station );
      block.images.push_back( image );
      import.imageIdBySourceName[label] = label;
      labelOfCamera[CPLGetXMLValue( node, "id", "" )] = label;
    } );
    if ( unaligned > 0 )
      import.dropped.push_back( std::to_string( unaligned ) + " camera(s) without a <transform> (not aligned in Metashape) were dropped" );
    if ( block.images.empty() )
      throw std::invalid_argument( "no camera of the Metashape file " + xmlFile.string() + " can be imported" + ( import.dropped.empty() ? std::string() : ": " + import.dropped.front() ) );
    import.converted.push_back( std::to_string( block.images.size() ) + " aligned camera(s) became oriented images, each its own station" );
    importMarkers( chunk, xmlFile, reference, geocentric, options.crs, labelOfCamera, import );

    block.sourceFile = imageFolder / "metashape-import.geostation.json";
    if ( options.requireImageFiles )
      for ( const BlockImage &image : block.images )
      {
        try
        {
          requireReadableImageFile( block, image );
        }
        catch ( const std::runtime_error &e )
        {
          throw std::invalid_argument( e.what() );
        }
      }
    return import;
  }

} // namespace geostation
