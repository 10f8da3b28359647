!> Coordinate-format (COO) sparse matrix builder for the implicit solvers.
!>
!> Each rank adds dense element blocks on global dof numbers; the entries are stored as
!> triplets (row, col, val) in the order they are added, duplicates included (MUMPS sums
!> them). Arrays grow by doubling, so adding never allocates per entry.
!>
!> Re-assembly with the same sparsity (Newton iterations): call coo_reset_values, then add
!> the same blocks again. Entries are matched by position, so the add order must be
!> identical to the first assembly; an entry that does not match (or one beyond the old
!> count) is stored anyway and marks the pattern as changed (new pattern_id), so the solver
!> knows it must analyse again. After coo_compress the entries are sorted and unique, and
!> a re-assembly finds each entry by binary search instead: any add order is then fine.
!>
!> Symmetric storage: with symmetric = .true. only the lower triangle (row >= col) of each
!> block is kept, which is what MUMPS expects for SYM = 1 or 2.
module mefem_sparse_assembly
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: fatal_local
  implicit none
  private

  public :: coo_init, coo_add_block, coo_add_rectangle, coo_reset_values, coo_compress, coo_free
  public :: STORAGE_EMPTY, STORAGE_FULL, STORAGE_LOWER, STORAGE_MIXED

  !> What coo_add_block was asked to store so far on this rank.
  integer, parameter :: STORAGE_EMPTY = 0  !< nothing added yet
  integer, parameter :: STORAGE_FULL = 1   !< whole blocks (unsymmetric storage)
  integer, parameter :: STORAGE_LOWER = 2  !< lower triangles only (symmetric storage)
  integer, parameter :: STORAGE_MIXED = 3  !< both kinds were added: an error for any solver

  integer(i8), parameter :: MIN_CAPACITY = 64_i8

  !> Last pattern identifier handed out (unique within the process).
  integer(i8) :: last_pattern_id = 0_i8

  !> This rank's share of a sparse matrix of global size n, as triplets.
  type, public :: coo_matrix_t
    integer :: n = 0                    !< number of global unknowns (rows = columns)
    integer(i8) :: nnz = 0_i8           !< number of stored entries (duplicates included)
    integer, allocatable :: row(:)      !< 1-based global row of each entry
    integer, allocatable :: col(:)      !< 1-based global column of each entry
    real(wp), allocatable :: val(:)     !< value of each entry
    integer :: storage = STORAGE_EMPTY  !< STORAGE_* of what has been added
    logical :: sorted = .false.         !< entries sorted by (row, col) and unique (compressed)
    integer(i8) :: cursor = 0_i8        !< entries added since coo_init / coo_reset_values
    integer(i8) :: pattern_id = 0_i8    !< changes whenever the positions of entries change
  end type coo_matrix_t

  !> Start an empty matrix of n unknowns with room for `capacity` entries (a hint).
  interface coo_init
    module procedure coo_init_i4, coo_init_i8
  end interface coo_init

contains

  !> coo_init with a default-integer capacity.
  subroutine coo_init_i4(a, n, capacity)
    type(coo_matrix_t), intent(out) :: a   !< the matrix
    integer, intent(in) :: n               !< number of global unknowns
    integer, intent(in) :: capacity        !< expected number of entries on this rank
    call coo_init_i8(a, n, int(capacity, i8))
  end subroutine coo_init_i4

  !> coo_init with a 64-bit capacity.
  subroutine coo_init_i8(a, n, capacity)
    type(coo_matrix_t), intent(out) :: a   !< the matrix
    integer, intent(in) :: n               !< number of global unknowns
    integer(i8), intent(in) :: capacity    !< expected number of entries on this rank
    integer(i8) :: c
    c = max(capacity, MIN_CAPACITY)
    a%n = n
    allocate(a%row(c), a%col(c), a%val(c))
    a%pattern_id = new_pattern_id()
  end subroutine coo_init_i8

  !> Release the storage.
  subroutine coo_free(a)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    if (allocated(a%row)) deallocate(a%row)
    if (allocated(a%col)) deallocate(a%col)
    if (allocated(a%val)) deallocate(a%val)
    a%n = 0
    a%nnz = 0_i8
    a%cursor = 0_i8
    a%storage = STORAGE_EMPTY
    a%sorted = .false.
  end subroutine coo_free

  !> Add a dense element block ke on the global dofs; dofs <= 0 (fixed) are skipped.
  subroutine coo_add_block(a, dofs, ke, symmetric)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    integer, intent(in) :: dofs(:)           !< global dof number of each block row/column
    real(wp), intent(in) :: ke(:,:)          !< block, size(dofs) x size(dofs)
    logical, intent(in) :: symmetric         !< store only the lower triangle (row >= col)
    call coo_add_rectangle(a, dofs, dofs, ke, symmetric)
  end subroutine coo_add_block

  !> Add a dense block ke on the global rows x columns; dofs <= 0 (fixed) are skipped.
  subroutine coo_add_rectangle(a, rows, cols, ke, symmetric)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    integer, intent(in) :: rows(:)           !< global dof number of each block row
    integer, intent(in) :: cols(:)           !< global dof number of each block column
    real(wp), intent(in) :: ke(:,:)          !< block, size(rows) x size(cols)
    logical, intent(in) :: symmetric         !< store only the lower triangle (row >= col)
    integer :: i, j, r, c
    logical :: changed
    character(len=160) :: text
    if (size(ke, 1) /= size(rows) .or. size(ke, 2) /= size(cols)) then
      write(text, '(a,i0,a,i0,a,i0,a,i0)') 'coo_add_block: block is ', size(ke, 1), ' x ', &
          size(ke, 2), ' for ', size(rows), ' x ', size(cols)
      call fatal_local(trim(text)//' dofs')
    end if
    do i = 1, size(rows) + size(cols)
      if (i <= size(rows)) then
        r = rows(i)
      else
        r = cols(i - size(rows))
      end if
      if (r > a%n) then
        write(text, '(a,i0,a,i0)') 'coo_add_block: dof ', r, ' exceeds the matrix size ', a%n
        call fatal_local(text)
      end if
    end do
    call record_storage(a, symmetric)
    call ensure_capacity(a, a%cursor + int(size(rows), i8)*int(size(cols), i8))
    changed = .false.
    do j = 1, size(cols)
      c = cols(j)
      if (c <= 0) cycle
      do i = 1, size(rows)
        r = rows(i)
        if (r <= 0) cycle
        if (symmetric .and. r < c) cycle
        call add_entry(a, r, c, ke(i, j), changed)
      end do
    end do
    if (changed) a%pattern_id = new_pattern_id()
  end subroutine coo_add_rectangle

  !> Zero the values and keep the positions, for a re-assembly with the same sparsity.
  !> Without coo_compress the blocks must then be added again in the identical order.
  subroutine coo_reset_values(a)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    if (a%nnz > 0_i8) a%val(1:a%nnz) = 0.0_wp
    a%cursor = 0_i8
  end subroutine coo_reset_values

  !> Sort the entries by (row, col) and sum duplicates, then shrink the arrays to fit.
  !> Heap sort on a 64-bit key: O(nnz log nnz) time, one temporary key per entry.
  subroutine coo_compress(a)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    integer(i8), allocatable :: key(:)
    integer(i8) :: k, m, n
    if (a%sorted) return
    n = a%nnz
    allocate(key(n))
    do k = 1, n
      key(k) = int(a%row(k) - 1, i8)*int(a%n, i8) + int(a%col(k), i8)
    end do
    call heap_sort(key, a%val(1:n))
    m = 0_i8
    do k = 1, n
      if (m > 0_i8) then
        if (key(k) == key(m)) then
          a%val(m) = a%val(m) + a%val(k)
          cycle
        end if
      end if
      m = m + 1_i8
      key(m) = key(k)
      a%val(m) = a%val(k)
    end do
    call resize(a, max(m, MIN_CAPACITY))
    do k = 1, m
      a%row(k) = int((key(k) - 1_i8)/int(a%n, i8)) + 1
      a%col(k) = int(key(k) - int(a%row(k) - 1, i8)*int(a%n, i8))
    end do
    a%nnz = m
    a%cursor = m
    a%sorted = .true.
    a%pattern_id = new_pattern_id()
  end subroutine coo_compress

  !> Store one entry (r, c, v) at the next position, matching the kept pattern if any.
  subroutine add_entry(a, r, c, v, changed)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    integer, intent(in) :: r, c              !< global row and column
    real(wp), intent(in) :: v                !< value to add
    logical, intent(inout) :: changed        !< set when the pattern had to change
    integer(i8) :: k
    if (a%sorted) then
      k = find_sorted(a, r, c)
      if (k > 0_i8) then
        a%val(k) = a%val(k) + v
        return
      end if
      a%sorted = .false.      ! a new position: back to plain (appending) storage
      a%cursor = a%nnz
    end if
    a%cursor = a%cursor + 1_i8
    k = a%cursor
    if (k <= a%nnz) then
      if (a%row(k) == r .and. a%col(k) == c) then
        a%val(k) = a%val(k) + v
        return
      end if
    else
      call ensure_capacity(a, k)
      a%nnz = k
    end if
    a%row(k) = r
    a%col(k) = c
    a%val(k) = v
    changed = .true.
  end subroutine add_entry

  !> Position of entry (r, c) in sorted storage, or 0 if absent (binary search).
  integer(i8) function find_sorted(a, r, c)
    type(coo_matrix_t), intent(in) :: a   !< the matrix, sorted
    integer, intent(in) :: r, c           !< global row and column
    integer(i8) :: low, high, mid
    find_sorted = 0_i8
    low = 1_i8
    high = a%nnz
    do while (low <= high)
      mid = (low + high)/2_i8
      if (a%row(mid) < r .or. (a%row(mid) == r .and. a%col(mid) < c)) then
        low = mid + 1_i8
      else if (a%row(mid) == r .and. a%col(mid) == c) then
        find_sorted = mid
        return
      else
        high = mid - 1_i8
      end if
    end do
  end function find_sorted

  !> Remember whether full or lower-triangle blocks were added.
  subroutine record_storage(a, symmetric)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    logical, intent(in) :: symmetric         !< kind of the block being added
    integer :: kind
    kind = merge(STORAGE_LOWER, STORAGE_FULL, symmetric)
    if (a%storage == STORAGE_EMPTY) then
      a%storage = kind
    else if (a%storage /= kind) then
      a%storage = STORAGE_MIXED
    end if
  end subroutine record_storage

  !> Make room for at least `needed` entries, doubling the capacity.
  subroutine ensure_capacity(a, needed)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    integer(i8), intent(in) :: needed        !< entries that must fit
    integer(i8) :: c
    if (.not. allocated(a%row)) call fatal_local('coo_add_block: matrix used before coo_init')
    c = size(a%row, kind=i8)
    if (needed <= c) return
    do while (c < needed)
      c = 2_i8*c
    end do
    call resize(a, c)
  end subroutine ensure_capacity

  !> Reallocate the arrays to capacity c, keeping the first nnz entries.
  subroutine resize(a, c)
    type(coo_matrix_t), intent(inout) :: a   !< the matrix
    integer(i8), intent(in) :: c             !< new capacity (>= nnz)
    integer, allocatable :: itmp(:)
    real(wp), allocatable :: rtmp(:)
    integer(i8) :: n
    n = min(a%nnz, c)
    allocate(itmp(c))
    itmp(1:n) = a%row(1:n)
    call move_alloc(itmp, a%row)
    allocate(itmp(c))
    itmp(1:n) = a%col(1:n)
    call move_alloc(itmp, a%col)
    allocate(rtmp(c))
    rtmp(1:n) = a%val(1:n)
    call move_alloc(rtmp, a%val)
  end subroutine resize

  !> Sort key ascending in place, applying the same moves to val (heap sort).
  subroutine heap_sort(key, val)
    integer(i8), intent(inout) :: key(:)   !< sort keys
    real(wp), intent(inout) :: val(:)      !< values carried along
    integer(i8) :: n, k, last
    integer(i8) :: tk
    real(wp) :: tv
    n = size(key, kind=i8)
    do k = n/2_i8, 1_i8, -1_i8
      call sift_down(key, val, k, n)
    end do
    do last = n, 2_i8, -1_i8
      tk = key(1)
      key(1) = key(last)
      key(last) = tk
      tv = val(1)
      val(1) = val(last)
      val(last) = tv
      call sift_down(key, val, 1_i8, last - 1_i8)
    end do
  end subroutine heap_sort

  !> Restore the max-heap property below position `start` within key(1:n).
  subroutine sift_down(key, val, start, n)
    integer(i8), intent(inout) :: key(:)   !< heap of keys
    real(wp), intent(inout) :: val(:)      !< values carried along
    integer(i8), intent(in) :: start       !< position to sift
    integer(i8), intent(in) :: n           !< heap size
    integer(i8) :: parent, child, tk
    real(wp) :: tv
    parent = start
    tk = key(parent)
    tv = val(parent)
    do
      child = 2_i8*parent
      if (child > n) exit
      if (child < n) then
        if (key(child + 1_i8) > key(child)) child = child + 1_i8
      end if
      if (key(child) <= tk) exit
      key(parent) = key(child)
      val(parent) = val(child)
      parent = child
    end do
    key(parent) = tk
    val(parent) = tv
  end subroutine sift_down

  !> A new pattern identifier, unique within the process.
  integer(i8) function new_pattern_id()
    last_pattern_id = last_pattern_id + 1_i8
    new_pattern_id = last_pattern_id
  end function new_pattern_id

end module mefem_sparse_assembly
