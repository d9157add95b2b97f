/***************************************************************************
  matchimagecache.cpp
 ***************************************************************************/
#include "workstation/matchimagecache.h"

#include <algorithm>
#include <stdexcept>

#include "io/rasterfile.h"

namespace geostation
{

  MatchImageCache::MatchImageCache( size_t capacity )
    : mCapacity( std::max<size_t>( 1, capacity ) )
  {
  }

  MatchImageCache::Entry MatchImageCache::get( const std::string &path )
  {
    {
      std::unique_lock<std::mutex> lock( mMutex );
      mLoaded.wait( lock, [&] { return mLoading.count( path ) == 0; } );
      auto it = mEntries.find( path );
      if ( it != mEntries.end() )
      {
        mOrder.remove( path );
        mOrder.push_front( path );
        return it->second;
      }
      mLoading.insert( path );
    }
    Entry entry;
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
      mOrder.push_front( path );
      while ( mOrder.size() > mCapacity )
      {
        mEntries.erase( mOrder.back() );
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
  }

} // namespace geostation
