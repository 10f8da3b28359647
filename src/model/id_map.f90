!> Maps from user ids to 1-based indices: sorted ids with their positions, searched by
!> bisection (O(log n) per lookup, O(n log n) to build; no hashing needed). When the ids
!> are dense (as in nearly every deck: 1..n with few gaps), a direct table from id to
!> position is built as well, and lookups take one memory access.
module mefem_id_map
  use mefem_kinds, only: i8
  implicit none
  private

  public :: id_map_build, id_map_find, sort_with_index

  !> Sorted copy of a list of ids with the original positions.
  type, public :: id_map_t
    integer :: n = 0
    integer, allocatable :: ids(:)       !< (n) ids ascending
    integer, allocatable :: index(:)     !< (n) position of ids(k) in the original list
    integer :: lowest = 0                !< smallest id (offset of the direct table)
    integer, allocatable :: direct(:)    !< (largest - lowest + 1) position of each id, 0 =
                                         !< absent; allocated only when the ids are dense
  end type id_map_t

  !> The direct table is built when it has at most this many entries per id (plus a few).
  integer, parameter :: DIRECT_SLACK = 2

contains

  !> Build the map of ids(1:n). Duplicated ids stay adjacent (the caller reports them).
  subroutine id_map_build(ids, n, map)
    integer, intent(in) :: ids(:)          !< user ids in deck order
    integer, intent(in) :: n               !< how many of them are used
    type(id_map_t), intent(out) :: map     !< the map
    integer :: k
    map%n = n
    allocate(map%ids(n), map%index(n))
    map%ids = ids(1:n)
    map%index = [(k, k = 1, n)]
    call sort_with_index(map%ids, map%index)
    if (n == 0) return
    if (int(map%ids(n), i8) - int(map%ids(1), i8) + 1_i8 > DIRECT_SLACK*int(n, i8) + 64_i8) &
      return
    map%lowest = map%ids(1)
    allocate(map%direct(map%ids(n) - map%lowest + 1))
    map%direct = 0
    ! backwards, so that a duplicated id keeps its first occurrence (as the bisection does)
    do k = n, 1, -1
      map%direct(map%ids(k) - map%lowest + 1) = map%index(k)
    end do
  end subroutine id_map_build

  !> Index of id in the original list, 0 when absent (first occurrence of a duplicate).
  pure integer function id_map_find(map, id)
    type(id_map_t), intent(in) :: map   !< the map
    integer, intent(in) :: id           !< id looked for
    integer :: lo, hi, mid
    integer(i8) :: offset
    id_map_find = 0
    if (allocated(map%direct)) then
      offset = int(id, i8) - int(map%lowest, i8)
      if (offset >= 0_i8 .and. offset < size(map%direct, kind=i8)) &
        id_map_find = map%direct(offset + 1_i8)
      return
    end if
    lo = 1
    hi = map%n
    do while (lo <= hi)
      mid = (lo + hi)/2
      if (map%ids(mid) < id) then
        lo = mid + 1
      else if (map%ids(mid) > id) then
        hi = mid - 1
      else
        do while (mid > 1)
          if (map%ids(mid-1) /= id) exit
          mid = mid - 1
        end do
        id_map_find = map%index(mid)
        return
      end if
    end do
  end function id_map_find

  !> Sort keys ascending, carrying values along (stable merge sort, O(n log n)).
  subroutine sort_with_index(keys, values)
    integer, intent(inout) :: keys(:)     !< keys, sorted on return
    integer, intent(inout) :: values(:)   !< values moved with their keys
    integer, allocatable :: kbuf(:), vbuf(:)
    integer :: n, width, lo, mid, hi, i, j, k
    n = size(keys)
    if (n < 2) return
    ! already in order (the usual case for ids written by pre-processors): nothing to do
    do i = 2, n
      if (keys(i) < keys(i-1)) exit
    end do
    if (i > n) return
    allocate(kbuf(n), vbuf(n))
    width = 1
    do while (width < n)
      lo = 1
      do while (lo <= n)
        mid = min(lo + width - 1, n)
        hi = min(lo + 2*width - 1, n)
        i = lo
        j = mid + 1
        do k = lo, hi
          if (i <= mid .and. (j > hi .or. keys(min(i, n)) <= keys(min(j, n)))) then
            kbuf(k) = keys(i)
            vbuf(k) = values(i)
            i = i + 1
          else
            kbuf(k) = keys(j)
            vbuf(k) = values(j)
            j = j + 1
          end if
        end do
        lo = hi + 1
      end do
      keys = kbuf
      values = vbuf
      width = 2*width
    end do
  end subroutine sort_with_index

end module mefem_id_map
