// Typed integer ids and the arenas they index: the "pointers" of the winged-edge B-Rep.
// An id is an index into one arena, -1 when invalid; ids of different element kinds do not
// convert into each other. Arenas never move or reuse a slot: a removed element leaves a
// tombstone, so an id stays meaningful (and detectably dead) after removal.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "kernel/error.h"

namespace wedge {

template <class Tag>
struct Id {
  std::int32_t value = -1;

  constexpr Id() = default;
  constexpr explicit Id(std::int32_t v) : value(v) {}
  constexpr bool valid() const { return value >= 0; }
  constexpr explicit operator bool() const { return valid(); }
  constexpr auto operator<=>(const Id&) const = default;
};

template <class T, class IdT>
class Arena {
 public:
  IdT add(T item) {
    items_.push_back(std::move(item));
    alive_.push_back(true);
    ++live_;
    return IdT(static_cast<std::int32_t>(items_.size() - 1));
  }
  void remove(IdT id) {
    check(id);
    alive_[static_cast<std::size_t>(id.value)] = false;
    --live_;
  }
  // Brings a removed element back (the inverse of remove), with its stored value.
  void restore(IdT id) {
    if (!id.valid() || static_cast<std::size_t>(id.value) >= items_.size() || alive_[id.value])
      fail("Arena::restore: id ", id.value, " is not a removed element");
    alive_[static_cast<std::size_t>(id.value)] = true;
    ++live_;
  }
  bool contains(IdT id) const {
    return id.valid() && static_cast<std::size_t>(id.value) < items_.size() && alive_[id.value];
  }
  T& operator[](IdT id) { check(id); return items_[static_cast<std::size_t>(id.value)]; }
  const T& operator[](IdT id) const { check(id); return items_[static_cast<std::size_t>(id.value)]; }

  std::size_t size() const { return live_; }          // live elements
  std::size_t capacity() const { return items_.size(); }  // slots ever used

  // The live ids, in creation order.
  std::vector<IdT> ids() const {
    std::vector<IdT> out;
    out.reserve(live_);
    for (std::size_t i = 0; i < items_.size(); ++i)
      if (alive_[i]) out.push_back(IdT(static_cast<std::int32_t>(i)));
    return out;
  }
  template <class F>
  void for_each(F&& f) const {
    for (std::size_t i = 0; i < items_.size(); ++i)
      if (alive_[i]) f(IdT(static_cast<std::int32_t>(i)), items_[i]);
  }

 private:
  void check(IdT id) const {
    if (!contains(id)) fail("invalid or removed id ", id.value);
  }
  std::vector<T> items_;
  std::vector<bool> alive_;
  std::size_t live_ = 0;
};

}  // namespace wedge

template <class Tag>
struct std::hash<wedge::Id<Tag>> {
  std::size_t operator()(const wedge::Id<Tag>& id) const noexcept { return std::hash<std::int32_t>()(id.value); }
};
