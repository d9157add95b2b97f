/***************************************************************************
  imageprefetcher.h - preparing the next images in the background
  -------------------------------------------------------------------------
  While the operator looks at a station, the Multiview prepares the images
  of that station and of the next one for matching (MatchImageCache), so
  that the first click there does not wait for reading and filtering
  (tens of milliseconds a full-HD frame, seconds for a large one).

  One worker thread of its own loads the requests in order. A new request
  replaces those not started yet: the operator stepping along the run
  faster than images load wants the station now shown, not those passed.
  The destructor drops what is pending and waits for the load in progress,
  so no load outlives its owner (nor the plugin library holding its code).
 ***************************************************************************/
#ifndef GEOSTATION_WORKSTATION_IMAGEPREFETCHER_H
#define GEOSTATION_WORKSTATION_IMAGEPREFETCHER_H

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace geostation
{

  class MatchImageCache;

  class ImagePrefetcher
  {
    public:
      //! Loads one image; an exception it throws counts as a failed load and the worker goes on.
      using LoadFunction = std::function<void( const std::string &path )>;

      //! Prepares images into `cache` (MatchImageCache::get(), which a reader waits on for a load in progress).
      explicit ImagePrefetcher( std::shared_ptr<MatchImageCache> cache );
      //! Any loading, e.g. for a test. Throws std::invalid_argument for an empty function.
      explicit ImagePrefetcher( LoadFunction load );
      //! Drops the pending requests and waits for the load in progress.
      ~ImagePrefetcher();

      ImagePrefetcher( const ImagePrefetcher & ) = delete;
      ImagePrefetcher &operator=( const ImagePrefetcher & ) = delete;

      /**
       * Loads `paths` in this order, in the background, instead of any
       * request not started yet (those count as superseded). Empty paths
       * and repeats are skipped. Returns at once.
       */
      void prefetch( const std::vector<std::string> &paths );

      //! Waits until nothing is pending or loading; false when `timeout` passed first.
      bool waitUntilIdle( std::chrono::milliseconds timeout ) const;

      struct Summary
      {
        size_t requested = 0;  //!< paths asked for
        size_t loaded = 0;     //!< loads done (whether the image could be read is the cache's entry)
        size_t failed = 0;     //!< loads that threw instead (out of memory, say)
        size_t superseded = 0; //!< dropped by a newer request or the destructor before they started
      };
      Summary summary() const;

    private:
      void run();

      LoadFunction mLoad;
      mutable std::mutex mMutex;
      mutable std::condition_variable mChanged;
      std::deque<std::string> mPending;
      bool mLoading = false;
      bool mStopping = false;
      Summary mSummary;
      std::thread mWorker; //!< last: started once the rest is set up
  };

} // namespace geostation

#endif // GEOSTATION_WORKSTATION_IMAGEPREFETCHER_H
