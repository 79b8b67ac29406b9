// Typed integer ids and the arenas they index: the "pointers" of the winged-edge B-Rep.
// An id is an index into one arena, -1 when invalid; ids of different element kinds do not
// convert into each other. Arenas never move or reuse a slot: a removed element leaves a
// tombstone, so an id stays meaningful (and detectably dead) after removal.
#pragma once
#include <cstdint>
#include <functional>
#include <type_traits>
#include <utility>
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


// Data attached to the elements of an arena by id, in the style of geometry-central's MeshData:
// `map[id]` reads or writes the value of one element (growing the store on write), and
// `for (auto [id, value] : map)` visits every slot that was ever written, in id order. Values of
// removed elements stay (an inverse operator brings the element and its value back).
template <class IdT, class T>
class IdMap {
 public:
  // The value for id, default-constructed the first time it is written.
  T& operator[](IdT id) {
    if (!id.valid()) fail("IdMap: invalid id");
    std::size_t i = static_cast<std::size_t>(id.value);
    if (i >= values_.size()) {
      values_.resize(i + 1);
      set_.resize(i + 1, false);
    }
    set_[i] = true;
    return values_[i];
  }
  const T& operator[](IdT id) const {
    if (!contains(id)) fail("IdMap: no value for id ", id.value);
    return values_[static_cast<std::size_t>(id.value)];
  }
  bool contains(IdT id) const {
    return id.valid() && static_cast<std::size_t>(id.value) < values_.size() && set_[static_cast<std::size_t>(id.value)];
  }
  std::size_t capacity() const { return values_.size(); }

  template <class V>
  class Iter {
   public:
    Iter(V* values, const std::vector<bool>* set, std::size_t i) : values_(values), set_(set), i_(i) { skip(); }
    using Ref = std::conditional_t<std::is_const_v<V>, const T&, T&>;
    std::pair<IdT, Ref> operator*() const {
      return {IdT(static_cast<std::int32_t>(i_)), (*values_)[i_]};
    }
    Iter& operator++() {
      ++i_;
      skip();
      return *this;
    }
    bool operator!=(const Iter& o) const { return i_ != o.i_; }

   private:
    void skip() {
      while (i_ < set_->size() && !(*set_)[i_]) ++i_;
    }
    V* values_;
    const std::vector<bool>* set_;
    std::size_t i_;
  };
  Iter<std::vector<T>> begin() { return {&values_, &set_, 0}; }
  Iter<std::vector<T>> end() { return {&values_, &set_, values_.size()}; }
  Iter<const std::vector<T>> begin() const { return {&values_, &set_, 0}; }
  Iter<const std::vector<T>> end() const { return {&values_, &set_, values_.size()}; }

 private:
  std::vector<T> values_;
  std::vector<bool> set_;
};

}  // namespace wedge

template <class Tag>
struct std::hash<wedge::Id<Tag>> {
  std::size_t operator()(const wedge::Id<Tag>& id) const noexcept { return std::hash<std::int32_t>()(id.value); }
};
