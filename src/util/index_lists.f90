!> Helpers for lists kept as one array with a start per group (CSR-style index lists).
module mefem_index_lists
  implicit none
  private

  public :: counts_to_starts, sort_small

contains

  !> Starts of groups from their counts: start(1) = first, start(k+1) = start(k) + counts(k);
  !> counts becomes start(1:n), the next free place of each group (fill, then counts(k) is
  !> the end of group k). first = 1 for 1-based lists, 0 for offsets.
  pure subroutine counts_to_starts(counts, start, first)
    integer, intent(inout) :: counts(:)               !< (n) counts in, next free places out
    integer, intent(out) :: start(:)                  !< (n+1) starts
    integer, intent(in) :: first                      !< start of the first group
    integer :: k
    start(1) = first
    do k = 1, size(counts)
      start(k + 1) = start(k) + counts(k)
    end do
    counts = start(1:size(counts))
  end subroutine counts_to_starts

  !> Sort a short list of integers ascending (insertion sort).
  pure subroutine sort_small(list)
    integer, intent(inout) :: list(:)                 !< the list
    integer :: i, j, v
    do i = 2, size(list)
      v = list(i)
      j = i - 1
      do while (j >= 1)
        if (list(j) <= v) exit
        list(j + 1) = list(j)
        j = j - 1
      end do
      list(j + 1) = v
    end do
  end subroutine sort_small

end module mefem_index_lists
