/***************************************************************************
  blockexport.cpp - a block handed back: COLMAP text model, orientation CSV
 ***************************************************************************/
#include "io/blockexport.h"

#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include "io/colmapconversion.h"
#include "io/textfile.h"

namespace fs = std::filesystem;

namespace geostation
{
  namespace
  {
    void moveInto( const fs::path &from, const fs::path &to )
    {
      std::error_code ec;
      fs::rename( from, to, ec );
      if ( ec )
        throw std::runtime_error( "cannot write " + to.string() + ": " + ec.message() );
    }
  }

  ColmapModel colmapModelFromBlock( const Block &block, const std::vector<ImportedTiePoint> &tiePoints, const std::vector<ImportedObservation> &observations,
                                    BlockExportSummary *summary )
  {
    BlockExportSummary local;
    BlockExportSummary &s = summary ? *summary : local;
    ColmapModel model;
    std::map<std::string, std::uint32_t> colmapCameraId;
    for ( const Camera &camera : block.cameras )
    {
      const CameraToColmap c = colmapCameraFromCamera( camera, static_cast<std::uint32_t>( model.cameras.size() + 1 ) );
      if ( !c.ok() )
      {
        s.dropped.push_back( c.message + "; its images were left out" );
        continue;
      }
      colmapCameraId[camera.id] = c.camera.id;
      model.cameras.push_back( c.camera );
    }

    std::map<std::string, size_t> imageIndex;
    for ( const BlockImage &image : block.images )
    {
      if ( !colmapCameraId.count( image.cameraId ) )
        continue;
      if ( !image.exterior )
      {
        s.dropped.push_back( "image \"" + image.id + "\" is not oriented and was left out" );
        continue;
      }
      if ( image.innerOrientation )
      {
        s.dropped.push_back( "image \"" + image.id + "\" is a scanned photo with an inner orientation, which a COLMAP model cannot hold; left out" );
        continue;
      }
      ColmapImage im;
      im.id = static_cast<std::uint32_t>( model.images.size() + 1 );
      im.cameraId = colmapCameraId[image.cameraId];
      im.name = image.path;
      colmapPoseFromExterior( *image.exterior, &im.qvec, &im.tvec );
      imageIndex[image.id] = model.images.size();
      model.images.push_back( im );
    }
    if ( model.images.empty() )
      throw std::invalid_argument( "the block has no image a COLMAP model can hold" + ( s.dropped.empty() ? std::string() : ": " + s.dropped.front() ) );

    std::map<std::string, std::vector<const ImportedObservation *>> observationsOf;
    for ( const ImportedObservation &o : observations )
      if ( imageIndex.count( o.imageId ) )
        observationsOf[o.pointId].push_back( &o );
    std::uint64_t nextId = 1;
    for ( const ImportedTiePoint &p : tiePoints )
    {
      auto it = observationsOf.find( p.pointId );
      if ( it == observationsOf.end() )
        continue;
      ColmapPoint3D point;
      point.id = nextId++;
      point.xyz = p.world;
      point.error = p.errorPx;
      for ( const ImportedObservation *o : it->second )
      {
        ColmapImage &im = model.images[imageIndex[o->imageId]];
        ColmapTrackElement t;
        t.imageId = im.id;
        t.point2DIndex = static_cast<std::uint32_t>( im.points2D.size() );
        ColmapPoint2D p2;
        p2.pixel = o->pixelInImage;
        p2.point3DId = static_cast<std::int64_t>( point.id );
        im.points2D.push_back( p2 );
        point.track.push_back( t );
      }
      model.points3D.push_back( point );
    }
    s.cameras = static_cast<int>( model.cameras.size() );
    s.images = static_cast<int>( model.images.size() );
    s.tiePoints = static_cast<int>( model.points3D.size() );
    return model;
  }

  BlockExportSummary exportBlockAsColmap( const Block &block, const fs::path &folder, const std::vector<ImportedTiePoint> &tiePoints,
                                          const std::vector<ImportedObservation> &observations )
  {
    BlockExportSummary summary;
    const ColmapModel model = colmapModelFromBlock( block, tiePoints, observations, &summary );
    std::error_code ec;
    fs::create_directories( folder, ec );
    if ( !fs::is_directory( folder, ec ) )
      throw std::runtime_error( "cannot create the folder " + folder.string() );
    fs::path staging = folder / ".geostation-export";
    fs::remove_all( staging, ec );
    try
    {
      model.writeText( staging );
      for ( const char *name : { "cameras.txt", "images.txt", "points3D.txt" } )
        moveInto( staging / name, folder / name );
    }
    catch ( ... )
    {
      fs::remove_all( staging, ec );
      throw;
    }
    fs::remove_all( staging, ec );
    return summary;
  }

  BlockExportSummary exportBlockAsCsv( const Block &block, const fs::path &file )
  {
    BlockExportSummary summary;
    std::ostringstream out;
    out << std::setprecision( 17 );
    out << "image_id,camera,station,path,X,Y,Z,omega,phi,kappa,sigma_X,sigma_Y,sigma_Z,sigma_omega,sigma_phi,sigma_kappa\n";
    for ( const BlockImage &image : block.images )
    {
      out << csvField( image.id ) << ',' << csvField( image.cameraId ) << ',' << csvField( image.stationId ) << ',' << csvField( image.path );
      if ( image.exterior )
      {
        const ExteriorOrientation &e = *image.exterior;
        out << ',' << e.projectionCentre.x() << ',' << e.projectionCentre.y() << ',' << e.projectionCentre.z() << ',' << e.omegaDeg << ',' << e.phiDeg << ',' << e.kappaDeg;
        if ( e.sigma )
          out << ',' << e.sigma->x << ',' << e.sigma->y << ',' << e.sigma->z << ',' << e.sigma->omegaDeg << ',' << e.sigma->phiDeg << ',' << e.sigma->kappaDeg;
        else
          out << ",,,,,,";
        ++summary.images;
      }
      else
      {
        out << ",,,,,,,,,,,,";
        summary.dropped.push_back( "image \"" + image.id + "\" is not oriented: its row has no orientation" );
      }
      out << '\n';
    }
    summary.cameras = static_cast<int>( block.cameras.size() );
    writeTextFileAtomically( file, out.str() );
    return summary;
  }

} // namespace geostation
