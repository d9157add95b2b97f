/***************************************************************************
  matchimagecache.cpp
 ***************************************************************************/
#include "workstation/matchimagecache.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "io/rasterfile.h"

namespace geostation
{

  MatchImageCache::MatchImageCache( size_t capacity, size_t maxBytes )
    : mCapacity( std::max<size_t>( 1, capacity ) )
    , mMaxBytes( maxBytes )
  {
  }

  size_t MatchImageCache::bytes() const
  {
    std::lock_guard<std::mutex> lock( mMutex );
    return mBytes;
  }

  namespace
  {
    //! "absent", or the file's size and last write time: what makes a remembered error stale.
    std::string fileStamp( const std::string &path )
    {
      std::error_code ec;
      const auto size = std::filesystem::file_size( path, ec );
      if ( ec )
        return "absent";
      const auto time = std::filesystem::last_write_time( path, ec );
      return std::to_string( size ) + "@" + std::to_string( ec ? 0 : time.time_since_epoch().count() );
    }
  }

  MatchImageCache::Entry MatchImageCache::get( const std::string &path )
  {
    {
      std::unique_lock<std::mutex> lock( mMutex );
      mLoaded.wait( lock, [&] { return mLoading.count( path ) == 0; } );
      auto it = mEntries.find( path );
      if ( it != mEntries.end() && !it->second.image && mErrorStamps[path] != fileStamp( path ) )
      {
        // the file was put back or rewritten since it failed: read it again
        mEntries.erase( it ); // (an error holds no bytes)
        mOrder.remove( path );
        it = mEntries.end();
      }
      if ( it != mEntries.end() )
      {
        mOrder.remove( path );
        mOrder.push_front( path );
        return it->second;
      }
      mLoading.insert( path );
    }
    Entry entry;
    const std::string stamp = fileStamp( path );
    try
    {
      entry.image = std::make_shared<const MatchImage>( readRaster( path ).pixels );
    }
    catch ( const std::exception &e )
    {
      entry.error = e.what();
    }
    {
      std::lock_guard<std::mutex> lock( mMutex );
      mLoading.erase( path );
      mEntries[path] = entry;
      mBytes += entry.image ? entry.image->bytes() : 0;
      if ( entry.image )
        mErrorStamps.erase( path );
      else
        mErrorStamps[path] = stamp;
      mOrder.push_front( path );
      while ( mOrder.size() > mCapacity || ( mOrder.size() > 1 && mBytes > mMaxBytes ) )
      {
        const Entry &oldest = mEntries.at( mOrder.back() );
        mBytes -= oldest.image ? oldest.image->bytes() : 0;
        mEntries.erase( mOrder.back() );
        mErrorStamps.erase( mOrder.back() );
        mOrder.pop_back();
      }
    }
    mLoaded.notify_all();
    return entry;
  }

  bool MatchImageCache::contains( const std::string &path ) const
  {
    std::lock_guard<std::mutex> lock( mMutex );
    return mEntries.count( path ) > 0;
  }

  void MatchImageCache::clear()
  {
    std::lock_guard<std::mutex> lock( mMutex );
    mEntries.clear();
    mOrder.clear();
    mErrorStamps.clear();
    mBytes = 0;
  }

} // namespace geostation
