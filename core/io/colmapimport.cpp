/***************************************************************************
  colmapimport.cpp - a COLMAP sparse model as a GeoStation block
 ***************************************************************************/
#include "io/colmapimport.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "geometry/crs.h"
#include "io/colmapconversion.h"

namespace fs = std::filesystem;

namespace geostation
{
  namespace
  {
    //! Image ids: the name without its extension when that is unique, else the whole name.
    std::map<std::uint32_t, std::string> imageIds( const std::vector<const ColmapImage *> &images )
    {
      std::map<std::string, int> stemCount;
      for ( const ColmapImage *im : images )
        ++stemCount[fs::path( im->name ).replace_extension().generic_string()];
      std::map<std::uint32_t, std::string> ids;
      for ( const ColmapImage *im : images )
      {
        const std::string stem = fs::path( im->name ).replace_extension().generic_string();
        ids[im->id] = stemCount[stem] == 1 && !stem.empty() ? stem : im->name;
      }
      return ids;
    }
  }

  fs::path findColmapImageFolder( const ColmapModel &model, const fs::path &modelFolder )
  {
    if ( model.images.empty() )
      return {};
    const fs::path folder = fs::absolute( modelFolder ).lexically_normal();
    const fs::path parent = folder.parent_path();
    const fs::path grandparent = parent.parent_path();
    std::error_code ec;
    for ( const fs::path &candidate : { folder, parent / "images", grandparent / "images", parent, grandparent } )
      if ( fs::exists( candidate / model.images.front().name, ec ) )
        return candidate;
    return {};
  }

  BlockImportSummary importColmapModel( const ColmapModel &model, const fs::path &modelFolder, const ColmapImportOptions &options )
  {
    if ( options.crs.empty() )
      throw std::invalid_argument( "give the CRS the block is to be in (the model's own frame needs one too: a local engineering CRS in metres)" );
    requireProjectedMetricCrs( options.crs );

    BlockImportSummary import;
    bool binary = false;
    ColmapModel::modelFolder( modelFolder, &binary );
    import.format = binary ? "colmap-binary" : "colmap-text";
    Block &block = import.block;
    block.crs = options.crs;

    // cameras
    std::map<std::uint32_t, std::string> cameraIdOf;
    std::map<std::uint32_t, std::string> droppedCameraWhy;
    std::map<std::uint32_t, int> imagesPerCamera;
    for ( const ColmapImage &im : model.images )
      ++imagesPerCamera[im.cameraId];
    for ( const ColmapCamera &c : model.cameras )
    {
      std::string whyNot;
      std::optional<Camera> camera = cameraFromColmap( c, "camera" + std::to_string( c.id ), &whyNot );
      if ( !camera )
      {
        droppedCameraWhy[c.id] = whyNot;
        import.dropped.push_back( whyNot + "; its " + std::to_string( imagesPerCamera[c.id] ) + " image(s) were dropped" );
        continue;
      }
      cameraIdOf[c.id] = camera->id;
      import.converted.push_back( "COLMAP camera " + std::to_string( c.id ) + " (" + c.model + ") became camera \"" + camera->id + "\" with lens model "
                                  + distortionModelName( camera->distortion.model ) );
      block.cameras.push_back( *camera );
    }

    // images, in name order (capture order for most cameras' file names)
    std::vector<const ColmapImage *> images;
    std::set<std::uint32_t> seenIds;
    for ( const ColmapImage &im : model.images )
    {
      if ( !seenIds.insert( im.id ).second )
        throw std::invalid_argument( "the COLMAP model has image id " + std::to_string( im.id ) + " twice" );
      if ( !model.findCamera( im.cameraId ) )
        throw std::invalid_argument( "COLMAP image " + std::to_string( im.id ) + " (" + im.name + ") names camera " + std::to_string( im.cameraId ) + ", which the model does not have" );
      if ( cameraIdOf.count( im.cameraId ) )
        images.push_back( &im );
    }
    std::sort( images.begin(), images.end(), []( const ColmapImage *a, const ColmapImage *b ) { return a->name < b->name; } );
    const std::map<std::uint32_t, std::string> idOf = imageIds( images );
    std::map<std::uint32_t, const ColmapImage *> importedById;
    for ( const ColmapImage *im : images )
    {
      BlockImage image;
      image.id = idOf.at( im->id );
      image.cameraId = cameraIdOf.at( im->cameraId );
      image.stationId = image.id;
      image.path = im->name;
      try
      {
        image.exterior = exteriorFromColmapPose( im->qvec, im->tvec );
      }
      catch ( const std::invalid_argument &e )
      {
        import.dropped.push_back( "COLMAP image " + std::to_string( im->id ) + " (" + im->name + "): " + e.what() + "; dropped" );
        continue;
      }
      Station station;
      station.id = image.id;
      block.stations.push_back( station );
      block.images.push_back( image );
      import.imageIdBySourceName[im->name] = image.id;
      importedById[im->id] = im;
    }
    if ( block.images.empty() )
      throw std::invalid_argument( "no image of the COLMAP model can be imported"
                                   + ( import.dropped.empty() ? std::string( ": the model has no registered images" ) : ": " + import.dropped.front() ) );
    import.converted.push_back( std::to_string( block.images.size() ) + " registered image(s) became oriented images, each its own station (COLMAP has no exposure stations)" );

    // image files
    fs::path imageFolder = options.imageFolder;
    if ( imageFolder.empty() )
      imageFolder = findColmapImageFolder( model, modelFolder );
    if ( imageFolder.empty() )
    {
      if ( options.requireImageFiles )
        throw std::invalid_argument( "the images of the COLMAP model were not found: \"" + model.images.front().name + "\" is neither beside the model in "
                                     + fs::absolute( modelFolder ).lexically_normal().string() + " nor in an \"images\" folder above it; give the image folder" );
      imageFolder = modelFolder;
    }
    block.sourceFile = fs::absolute( imageFolder ) / "colmap-import.geostation.json";
    if ( options.requireImageFiles )
    {
      for ( const BlockImage &image : block.images )
      {
        try
        {
          requireReadableImageFile( block, image );
        }
        catch ( const std::runtime_error &e )
        {
          throw std::invalid_argument( std::string( e.what() ) + " (image folder " + imageFolder.string() + ")" );
        }
      }
    }

    // tie points: the 3-D points and their observations in the imported images
    int pointsDropped = 0;
    std::set<std::uint64_t> seenPoints;
    for ( const ColmapPoint3D &p : model.points3D )
    {
      if ( !seenPoints.insert( p.id ).second )
        throw std::invalid_argument( "the COLMAP model has 3-D point id " + std::to_string( p.id ) + " twice" );
      std::vector<ImportedObservation> observations;
      std::set<std::uint32_t> imagesSeen;
      for ( const ColmapTrackElement &t : p.track )
      {
        auto it = importedById.find( t.imageId );
        if ( it == importedById.end() )
          continue;
        const ColmapImage &im = *it->second;
        if ( t.point2DIndex >= im.points2D.size() )
          throw std::invalid_argument( "the COLMAP model is inconsistent: 3-D point " + std::to_string( p.id ) + " is observed as 2-D point " + std::to_string( t.point2DIndex )
                                       + " of image " + std::to_string( im.id ) + ", which has " + std::to_string( im.points2D.size() ) );
        if ( !imagesSeen.insert( im.id ).second )
          continue; // one observation per image and point
        ImportedObservation o;
        o.pointId = std::to_string( p.id );
        o.imageId = idOf.at( im.id );
        o.pixelInImage = im.points2D[t.point2DIndex].pixel;
        observations.push_back( o );
      }
      if ( observations.size() < 2 || !p.xyz.allFinite() )
      {
        ++pointsDropped;
        continue;
      }
      ImportedTiePoint tie;
      tie.pointId = std::to_string( p.id );
      tie.world = p.xyz;
      tie.errorPx = p.error;
      import.tiePoints.push_back( tie );
      import.observations.insert( import.observations.end(), observations.begin(), observations.end() );
    }
    if ( !model.points3D.empty() )
      import.converted.push_back( std::to_string( import.tiePoints.size() ) + " 3-D point(s) became tie points with " + std::to_string( import.observations.size() ) + " image observations" );
    if ( pointsDropped > 0 )
      import.dropped.push_back( std::to_string( pointsDropped ) + " 3-D point(s) seen in fewer than two imported images were dropped" );
    return import;
  }

} // namespace geostation
