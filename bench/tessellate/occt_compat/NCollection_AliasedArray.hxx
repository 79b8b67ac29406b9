// wedge's stand-in for OpenCASCADE 7.6's NCollection_AliasedArray.hxx, which Debian's OCCT 7.6.3
// packages do not ship although Poly_ArrayOfNodes.hxx (and so Poly_Triangulation.hxx) includes it.
// Written here from the class's documented interface: an array of fixed-stride elements read as
// any type of that size. Its data members must be laid out as in the library that Poly_Triangulation
// was compiled with (a byte pointer, the stride, the size, a flag saying who owns the memory); the
// bench checks this at run time (the nodes of a meshed unit sphere must lie on it).
#ifndef _NCollection_AliasedArray_HeaderFile
#define _NCollection_AliasedArray_HeaderFile

#include <Standard.hxx>
#include <Standard_DefineAlloc.hxx>
#include <Standard_OutOfRange.hxx>
#include <Standard_TypeMismatch.hxx>

#include <cstring>
#include <utility>

template <int MyAlignSize = 16>
class NCollection_AliasedArray {
 public:
  DEFINE_STANDARD_ALLOC

  explicit NCollection_AliasedArray(Standard_Integer theStride)
      : myData(NULL), myStride(theStride), mySize(0), myDeletable(Standard_False) {}

  NCollection_AliasedArray(Standard_Integer theStride, Standard_Integer theLength)
      : myData(NULL), myStride(theStride), mySize(theLength), myDeletable(Standard_True) {
    if (theLength <= 0 || myStride <= 0) throw Standard_RangeError("NCollection_AliasedArray: bad size");
    myData = static_cast<Standard_Byte*>(Standard::AllocateAligned(SizeBytes(), MyAlignSize));
  }

  template <typename Type_t>
  NCollection_AliasedArray(const Type_t& theBegin, Standard_Integer theLength)
      : myData((Standard_Byte*)&theBegin), myStride((int)sizeof(Type_t)), mySize(theLength), myDeletable(Standard_False) {}

  NCollection_AliasedArray(NCollection_AliasedArray&& theOther)
      : myData(theOther.myData), myStride(theOther.myStride), mySize(theOther.mySize), myDeletable(theOther.myDeletable) {
    theOther.myDeletable = Standard_False;
  }

  ~NCollection_AliasedArray() {
    if (myDeletable) Standard::FreeAligned(myData);
  }

  Standard_Integer Stride() const { return myStride; }
  Standard_Integer Size() const { return mySize; }
  Standard_Integer Length() const { return mySize; }
  Standard_Boolean IsEmpty() const { return mySize == 0; }
  Standard_Integer Lower() const { return 0; }
  Standard_Integer Upper() const { return mySize - 1; }
  Standard_Boolean IsDeletable() const { return myDeletable; }
  Standard_Boolean IsAllocated() const { return myDeletable; }
  Standard_Size SizeBytes() const { return size_t(myStride) * size_t(mySize); }

  NCollection_AliasedArray& Assign(const NCollection_AliasedArray& theOther) {
    if (&theOther == this) return *this;
    if (myStride != theOther.myStride || mySize != theOther.mySize) throw Standard_TypeMismatch("NCollection_AliasedArray::Assign");
    if (myData != NULL) std::memcpy(myData, theOther.myData, SizeBytes());
    return *this;
  }

  NCollection_AliasedArray& Move(NCollection_AliasedArray& theOther) {
    if (&theOther == this) return *this;
    if (myDeletable) Standard::FreeAligned(myData);
    myStride = theOther.myStride;
    mySize = theOther.mySize;
    myDeletable = theOther.myDeletable;
    myData = theOther.myData;
    theOther.myDeletable = Standard_False;
    return *this;
  }

  NCollection_AliasedArray& operator=(const NCollection_AliasedArray& theOther) { return Assign(theOther); }
  NCollection_AliasedArray& operator=(NCollection_AliasedArray&& theOther) { return Move(theOther); }

  void Resize(Standard_Integer theLength, Standard_Boolean theToCopyData) {
    if (theLength <= 0) throw Standard_RangeError("NCollection_AliasedArray::Resize");
    Standard_Byte* anOld = myData;
    Standard_Integer anOldSize = mySize;
    Standard_Boolean anOldDeletable = myDeletable;
    mySize = theLength;
    myData = static_cast<Standard_Byte*>(Standard::AllocateAligned(SizeBytes(), MyAlignSize));
    myDeletable = Standard_True;
    if (theToCopyData && anOld != NULL) std::memcpy(myData, anOld, size_t(myStride) * size_t(anOldSize < theLength ? anOldSize : theLength));
    if (anOldDeletable) Standard::FreeAligned(anOld);
  }

  template <typename Type_t>
  const Type_t& Value(Standard_Integer theIndex) const {
    Standard_OutOfRange_Raise_if(theIndex < 0 || theIndex >= mySize, "NCollection_AliasedArray::Value(), out of range index");
    return *reinterpret_cast<const Type_t*>(myData + size_t(myStride) * size_t(theIndex));
  }
  template <typename Type_t>
  void Value(Standard_Integer theIndex, Type_t& theValue) const {
    theValue = Value<Type_t>(theIndex);
  }
  template <typename Type_t>
  Type_t& ChangeValue(Standard_Integer theIndex) {
    Standard_OutOfRange_Raise_if(theIndex < 0 || theIndex >= mySize, "NCollection_AliasedArray::ChangeValue(), out of range index");
    return *reinterpret_cast<Type_t*>(myData + size_t(myStride) * size_t(theIndex));
  }
  template <typename Type_t>
  void SetValue(Standard_Integer theIndex, const Type_t& theItem) {
    ChangeValue<Type_t>(theIndex) = theItem;
  }
  template <typename Type_t>
  const Type_t& First() const { return Value<Type_t>(0); }
  template <typename Type_t>
  const Type_t& Last() const { return Value<Type_t>(mySize - 1); }

 protected:
  Standard_Byte* myData;
  Standard_Integer myStride;
  Standard_Integer mySize;
  Standard_Boolean myDeletable;
};

#endif
