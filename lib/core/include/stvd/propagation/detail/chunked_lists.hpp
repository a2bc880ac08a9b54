// A fixed number of append-only lists that share one pool of fixed-size
// chunks: the cold buckets of the front queue.
//
// Why not one std::vector per list: a vector keeps the capacity of its
// largest fill, and each of the queue's buckets fills up once per sweep of
// its key range, so the vectors together held several times the front (at
// 256^3, 237 MiB more than the live entries). Here a list that is drained
// gives its chunks back at once, and memory stays at the entries queued plus
// one partly filled chunk per list.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

namespace stvd::detail {

template <class T, int kChunkSize>
class ChunkedLists {
  static_assert(std::is_trivially_copyable_v<T>, "values are copied as bytes");
  static_assert(kChunkSize > 0, "a chunk holds at least one value");

 public:
  explicit ChunkedLists(std::size_t listCount) : lists_(listCount) {}
  ChunkedLists(const ChunkedLists&) = delete;
  ChunkedLists& operator=(const ChunkedLists&) = delete;

  bool empty(std::size_t list) const { return lists_[list].head == nullptr; }

  void append(std::size_t list, const T& value) {
    List& l = lists_[list];
    if (l.tail == nullptr || l.tailSize == kChunkSize) {
      Chunk* c = takeChunk();
      if (l.tail != nullptr)
        l.tail->next = c;
      else
        l.head = c;
      l.tail = c;
      l.tailSize = 0;
    }
    l.tail->value[l.tailSize++] = value;
  }

  /// Calls f(first, count) for each run of the list's values, in the order
  /// they were appended, and empties the list. The list is detached before
  /// the first call, so f may append to any list, this one included; each
  /// chunk goes back to the pool once f has seen it.
  template <class F>
  void drain(std::size_t list, F&& f) {
    List l = lists_[list];
    lists_[list] = List{};
    for (Chunk* c = l.head; c != nullptr;) {
      Chunk* next = c->next;
      f(static_cast<const T*>(c->value), c == l.tail ? l.tailSize : kChunkSize);
      giveBack(c);
      c = next;
    }
  }

  /// Calls f(first, count) for each run of the list's values, leaving them.
  template <class F>
  void forEachRun(std::size_t list, F&& f) const {
    const List& l = lists_[list];
    for (const Chunk* c = l.head; c != nullptr; c = c->next)
      f(static_cast<const T*>(c->value), c == l.tail ? l.tailSize : kChunkSize);
  }

  /// Bytes held: every chunk ever made (they are reused, not freed) and the
  /// list heads.
  std::size_t capacityBytes() const {
    return chunks_.size() * sizeof(Chunk) + chunks_.capacity() * sizeof(chunks_[0]) +
           lists_.capacity() * sizeof(List);
  }

 private:
  struct Chunk {
    T value[kChunkSize];
    Chunk* next;
  };
  struct List {
    Chunk* head = nullptr;
    Chunk* tail = nullptr;
    int tailSize = 0;  // values in the tail chunk
  };

  Chunk* takeChunk() {
    Chunk* c = free_;
    if (c != nullptr) {
      free_ = c->next;
    } else {
      chunks_.push_back(std::make_unique<Chunk>());
      c = chunks_.back().get();
    }
    c->next = nullptr;
    return c;
  }
  void giveBack(Chunk* c) {
    c->next = free_;
    free_ = c;
  }

  std::vector<List> lists_;
  std::vector<std::unique_ptr<Chunk>> chunks_;  // owns every chunk
  Chunk* free_ = nullptr;                       // chunks in no list
};

}  // namespace stvd::detail
