!> One rank's share of the mesh, built from the global mesh and an element partition.
!>
!> Every rank holds the global mesh and the same elem_part (computed on rank 0 and
!> broadcast by the caller) and builds its own decomposition_t here; there is no MPI in
!> this module. A rank gets the elements of its part and every node they touch. Each node
!> is owned by exactly one rank, the lowest rank among those whose elements touch it (nodes
!> touched by no element belong to rank 0 and are local there, so they are written once).
!> For each neighbour rank q, shared_nodes lists the local nodes also touched by q's
!> elements, in ascending global order, so the lists of p for q and of q for p name the
!> same nodes in the same order and halo buffers need no further matching.
!> The work per rank is linear in the size of the global mesh plus the number of ranks.
module mefem_decomposition
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t, fatal_local
  use mefem_output_mesh, only: output_mesh_t
  implicit none
  private

  public :: build_decomposition, fill_output_mesh

  !> This rank's elements and nodes, local connectivity, node ownership and halo pattern.
  type, public :: decomposition_t
    integer :: rank = 0                          !< this rank (0-based)
    integer :: nranks = 1                        !< number of ranks
    integer :: nelem_global = 0                  !< elements in the global mesh
    integer :: nnode_global = 0                  !< nodes in the global mesh
    integer :: nelem_local = 0                   !< elements of this rank
    integer, allocatable :: elem_global(:)       !< (nelem_local) global indices, ascending
    integer, allocatable :: elem_start_local(:)  !< (nelem_local+1) start of each element's nodes
    integer, allocatable :: elem_nodes_local(:)  !< local node indices of all local elements
    logical, allocatable :: elem_on_boundary(:)  !< (nelem_local) touches a node shared with
                                                 !< another rank ("outer" element)
    integer :: nnode_local = 0                   !< nodes touched by this rank's elements
    integer :: nnode_owned = 0                   !< local nodes this rank owns
    integer, allocatable :: node_global(:)       !< (nnode_local) global indices, ascending
    integer, allocatable :: node_owner(:)        !< (nnode_local) rank that owns the node
    logical, allocatable :: node_owned(:)        !< (nnode_local) node_owner == rank
    integer :: nneighbour = 0                    !< ranks sharing at least one node with us
    integer, allocatable :: neighbour_rank(:)    !< (nneighbour) their ranks, ascending
    integer, allocatable :: shared_start(:)      !< (nneighbour+1) neighbour k's nodes are at
                                                 !< shared_start(k):shared_start(k+1)-1
    integer, allocatable :: shared_nodes(:)      !< local node indices, ascending per neighbour
  end type decomposition_t

contains

  !> Build rank `rank`'s decomposition from the global mesh and the element partition.
  !> Invalid input sets status (or, without status, stops all ranks with a message).
  subroutine build_decomposition(rank, nranks, nelem, nnode, elem_start, elem_nodes, &
                                 elem_part, decomp, status)
    integer, intent(in) :: rank                   !< rank to build for, 0..nranks-1
    integer, intent(in) :: nranks                 !< number of ranks (parts)
    integer, intent(in) :: nelem                  !< elements in the global mesh
    integer, intent(in) :: nnode                  !< nodes in the global mesh
    integer, intent(in) :: elem_start(:)          !< (nelem+1) e has elem_start(e):elem_start(e+1)-1
    integer, intent(in) :: elem_nodes(:)          !< 1-based global node indices
    integer, intent(in) :: elem_part(:)           !< (nelem) rank of each element, 0..nranks-1
    type(decomposition_t), intent(out) :: decomp  !< the result
    type(status_t), intent(out), optional :: status !< failure and its reason
    integer, allocatable :: part_start(:), part_elems(:)
    integer, allocatable :: node_rank_start(:), node_ranks(:), global_to_local(:)
    type(status_t) :: check_status

    call check_decomposition_input(rank, nranks, nelem, nnode, elem_start, elem_nodes, &
                                   elem_part, check_status)
    if (present(status)) status = check_status
    if (.not. check_status%ok) then
      if (present(status)) return
      call fatal_local(check_status%message)
    end if

    decomp%rank = rank
    decomp%nranks = nranks
    decomp%nelem_global = nelem
    decomp%nnode_global = nnode

    call bucket_elements_by_part(nranks, elem_part(1:nelem), part_start, part_elems)
    call collect_node_ranks(nranks, nnode, elem_start, elem_nodes, part_start, part_elems, &
                            node_rank_start, node_ranks)

    ! This rank's elements: its bucket, already in ascending global order.
    decomp%nelem_local = part_start(rank + 1) - part_start(rank)
    decomp%elem_global = part_elems(part_start(rank) + 1:part_start(rank + 1))

    call select_local_nodes(decomp, node_rank_start, node_ranks, global_to_local)
    call localise_connectivity(decomp, elem_start, elem_nodes, global_to_local)
    call build_shared_lists(decomp, node_rank_start, node_ranks)
  end subroutine build_decomposition

  !> Check sizes, ranges and the CSR structure of the input.
  subroutine check_decomposition_input(rank, nranks, nelem, nnode, elem_start, elem_nodes, &
                                       elem_part, status)
    integer, intent(in) :: rank                   !< rank to build for
    integer, intent(in) :: nranks                 !< number of ranks
    integer, intent(in) :: nelem                  !< elements in the global mesh
    integer, intent(in) :: nnode                  !< nodes in the global mesh
    integer, intent(in) :: elem_start(:)          !< (nelem+1) element starts
    integer, intent(in) :: elem_nodes(:)          !< 1-based global node indices
    integer, intent(in) :: elem_part(:)           !< (nelem) rank of each element
    type(status_t), intent(inout) :: status       !< set on failure
    character(len=200) :: text
    integer :: e, nconn

    text = ''
    if (nranks < 1) then
      write(text, '(a,i0)') 'need at least one rank, got nranks = ', nranks
    else if (rank < 0 .or. rank >= nranks) then
      write(text, '(a,i0,a,i0)') 'rank ', rank, ' outside 0..', nranks - 1
    else if (nelem < 0 .or. nnode < 0) then
      write(text, '(a,i0,a,i0)') 'negative size: nelem = ', nelem, ', nnode = ', nnode
    else if (size(elem_start) < nelem + 1) then
      write(text, '(a,i0,a,i0)') 'elem_start has ', size(elem_start), ' entries, need ', nelem + 1
    else if (size(elem_part) < nelem) then
      write(text, '(a,i0,a,i0)') 'elem_part has ', size(elem_part), ' entries, need ', nelem
    else if (elem_start(1) /= 1) then
      write(text, '(a,i0)') 'elem_start(1) must be 1, got ', elem_start(1)
    end if
    if (len_trim(text) == 0) then
      do e = 1, nelem
        if (elem_start(e + 1) < elem_start(e)) then
          write(text, '(a,i0)') 'elem_start decreases at element ', e
          exit
        end if
      end do
    end if
    if (len_trim(text) == 0) then
      nconn = elem_start(nelem + 1) - 1
      if (nconn > size(elem_nodes)) then
        write(text, '(a,i0,a,i0)') 'elem_nodes has ', size(elem_nodes), ' entries, need ', nconn
      else if (nconn > 0) then
        if (any(elem_nodes(1:nconn) < 1) .or. any(elem_nodes(1:nconn) > nnode)) &
          write(text, '(a,i0)') 'a node index is outside 1..', nnode
      end if
    end if
    if (len_trim(text) == 0 .and. nelem > 0) then
      if (any(elem_part(1:nelem) < 0) .or. any(elem_part(1:nelem) >= nranks)) &
        write(text, '(a,i0)') 'an element part is outside 0..', nranks - 1
    end if
    if (len_trim(text) > 0) then
      status%ok = .false.
      status%message = 'build_decomposition: '//trim(text)
    end if
  end subroutine check_decomposition_input

  !> Counting sort of the elements by part: part r's elements, ascending, are
  !> part_elems(part_start(r)+1:part_start(r+1)).
  subroutine bucket_elements_by_part(nranks, elem_part, part_start, part_elems)
    integer, intent(in) :: nranks                         !< number of parts
    integer, intent(in) :: elem_part(:)                   !< (nelem) part of each element
    integer, allocatable, intent(out) :: part_start(:)    !< (0:nranks) bucket offsets
    integer, allocatable, intent(out) :: part_elems(:)    !< (nelem) elements sorted by part
    integer, allocatable :: next(:)
    integer :: e, r

    allocate(part_start(0:nranks), next(0:nranks - 1), part_elems(size(elem_part)))
    part_start = 0
    do e = 1, size(elem_part)
      part_start(elem_part(e) + 1) = part_start(elem_part(e) + 1) + 1
    end do
    do r = 1, nranks
      part_start(r) = part_start(r) + part_start(r - 1)
    end do
    next = part_start(0:nranks - 1)
    do e = 1, size(elem_part)
      next(elem_part(e)) = next(elem_part(e)) + 1
      part_elems(next(elem_part(e))) = e
    end do
  end subroutine bucket_elements_by_part

  !> For every node, the ranks whose elements touch it, ascending and without repeats:
  !> node n's ranks are node_ranks(node_rank_start(n):node_rank_start(n+1)-1). Visiting the
  !> parts in ascending order builds each list sorted, with one pass to count and one to fill.
  subroutine collect_node_ranks(nranks, nnode, elem_start, elem_nodes, part_start, part_elems, &
                                node_rank_start, node_ranks)
    integer, intent(in) :: nranks                         !< number of parts
    integer, intent(in) :: nnode                          !< nodes in the global mesh
    integer, intent(in) :: elem_start(:)                  !< element starts
    integer, intent(in) :: elem_nodes(:)                  !< 1-based global node indices
    integer, intent(in) :: part_start(0:)                 !< bucket offsets by part
    integer, intent(in) :: part_elems(:)                  !< elements sorted by part
    integer, allocatable, intent(out) :: node_rank_start(:) !< (nnode+1) list offsets
    integer, allocatable, intent(out) :: node_ranks(:)    !< ranks touching each node
    integer, allocatable :: last_rank(:), next(:)
    integer :: pass, r, k, e, j, n

    allocate(node_rank_start(nnode + 1), last_rank(nnode), next(nnode))
    node_rank_start = 0
    do pass = 1, 2
      last_rank = -1
      if (pass == 2) then
        node_rank_start(1) = 1
        do n = 1, nnode
          node_rank_start(n + 1) = node_rank_start(n) + next(n)
        end do
        allocate(node_ranks(node_rank_start(nnode + 1) - 1))
        next = node_rank_start(1:nnode)
      else
        next = 0
      end if
      do r = 0, nranks - 1
        do k = part_start(r) + 1, part_start(r + 1)
          e = part_elems(k)
          do j = elem_start(e), elem_start(e + 1) - 1
            n = elem_nodes(j)
            if (last_rank(n) == r) cycle
            last_rank(n) = r
            if (pass == 2) node_ranks(next(n)) = r
            next(n) = next(n) + 1
          end do
        end do
      end do
    end do
  end subroutine collect_node_ranks

  !> Choose the local nodes (ascending global order), their owners, and the global-to-local map.
  subroutine select_local_nodes(decomp, node_rank_start, node_ranks, global_to_local)
    type(decomposition_t), intent(inout) :: decomp        !< rank and sizes in, nodes out
    integer, intent(in) :: node_rank_start(:)             !< (nnode+1) list offsets
    integer, intent(in) :: node_ranks(:)                  !< ranks touching each node
    integer, allocatable, intent(out) :: global_to_local(:) !< (nnode) local index or 0
    integer :: n, j, nlocal, owner
    logical :: mine

    allocate(global_to_local(decomp%nnode_global))
    global_to_local = 0
    nlocal = 0
    do n = 1, decomp%nnode_global
      if (node_rank_start(n + 1) == node_rank_start(n)) then
        mine = decomp%rank == 0          ! untouched node: rank 0 keeps it
      else
        mine = .false.
        do j = node_rank_start(n), node_rank_start(n + 1) - 1
          if (node_ranks(j) == decomp%rank) mine = .true.
        end do
      end if
      if (mine) then
        nlocal = nlocal + 1
        global_to_local(n) = nlocal
      end if
    end do

    decomp%nnode_local = nlocal
    allocate(decomp%node_global(nlocal), decomp%node_owner(nlocal), decomp%node_owned(nlocal))
    do n = 1, decomp%nnode_global
      if (global_to_local(n) == 0) cycle
      owner = 0
      if (node_rank_start(n + 1) > node_rank_start(n)) owner = node_ranks(node_rank_start(n))
      decomp%node_global(global_to_local(n)) = n
      decomp%node_owner(global_to_local(n)) = owner
    end do
    decomp%node_owned = decomp%node_owner == decomp%rank
    decomp%nnode_owned = count(decomp%node_owned)
  end subroutine select_local_nodes

  !> Local connectivity of this rank's elements, in local node numbers.
  subroutine localise_connectivity(decomp, elem_start, elem_nodes, global_to_local)
    type(decomposition_t), intent(inout) :: decomp        !< local elements in, connectivity out
    integer, intent(in) :: elem_start(:)                  !< global element starts
    integer, intent(in) :: elem_nodes(:)                  !< global node indices
    integer, intent(in) :: global_to_local(:)             !< (nnode) local index or 0
    integer :: i, e, j, k, nconn

    allocate(decomp%elem_start_local(decomp%nelem_local + 1))
    decomp%elem_start_local(1) = 1
    do i = 1, decomp%nelem_local
      e = decomp%elem_global(i)
      decomp%elem_start_local(i + 1) = decomp%elem_start_local(i) + &
                                       (elem_start(e + 1) - elem_start(e))
    end do
    nconn = decomp%elem_start_local(decomp%nelem_local + 1) - 1
    allocate(decomp%elem_nodes_local(nconn))
    do i = 1, decomp%nelem_local
      e = decomp%elem_global(i)
      k = decomp%elem_start_local(i)
      do j = elem_start(e), elem_start(e + 1) - 1
        decomp%elem_nodes_local(k) = global_to_local(elem_nodes(j))
        k = k + 1
      end do
    end do
  end subroutine localise_connectivity

  !> Neighbour ranks, the local nodes shared with each, and the boundary ("outer") elements.
  subroutine build_shared_lists(decomp, node_rank_start, node_ranks)
    type(decomposition_t), intent(inout) :: decomp        !< local nodes in, halo pattern out
    integer, intent(in) :: node_rank_start(:)             !< (nnode+1) list offsets
    integer, intent(in) :: node_ranks(:)                  !< ranks touching each node
    integer, allocatable :: shared_count(:), neighbour_of_rank(:), next(:)
    logical, allocatable :: node_shared(:)
    integer :: i, n, j, q, k

    allocate(shared_count(0:decomp%nranks - 1), neighbour_of_rank(0:decomp%nranks - 1))
    allocate(node_shared(decomp%nnode_local))
    shared_count = 0
    do i = 1, decomp%nnode_local
      n = decomp%node_global(i)
      node_shared(i) = node_rank_start(n + 1) - node_rank_start(n) > 1
      do j = node_rank_start(n), node_rank_start(n + 1) - 1
        q = node_ranks(j)
        if (q /= decomp%rank) shared_count(q) = shared_count(q) + 1
      end do
    end do

    decomp%nneighbour = count(shared_count > 0)
    allocate(decomp%neighbour_rank(decomp%nneighbour), decomp%shared_start(decomp%nneighbour + 1))
    neighbour_of_rank = 0
    decomp%shared_start(1) = 1
    k = 0
    do q = 0, decomp%nranks - 1
      if (shared_count(q) == 0) cycle
      k = k + 1
      decomp%neighbour_rank(k) = q
      neighbour_of_rank(q) = k
      decomp%shared_start(k + 1) = decomp%shared_start(k) + shared_count(q)
    end do

    ! Local nodes are visited in ascending order, so every list comes out sorted.
    allocate(decomp%shared_nodes(decomp%shared_start(decomp%nneighbour + 1) - 1))
    allocate(next(decomp%nneighbour))
    next(:) = decomp%shared_start(1:decomp%nneighbour)
    do i = 1, decomp%nnode_local
      n = decomp%node_global(i)
      do j = node_rank_start(n), node_rank_start(n + 1) - 1
        q = node_ranks(j)
        if (q == decomp%rank) cycle
        k = neighbour_of_rank(q)
        decomp%shared_nodes(next(k)) = i
        next(k) = next(k) + 1
      end do
    end do

    allocate(decomp%elem_on_boundary(decomp%nelem_local))
    do i = 1, decomp%nelem_local
      k = decomp%elem_start_local(i)
      decomp%elem_on_boundary(i) = &
          any(node_shared(decomp%elem_nodes_local(k:decomp%elem_start_local(i + 1) - 1)))
    end do
  end subroutine build_shared_lists

  !> Fill the writers' view of this rank's piece from the global model arrays.
  !> global_node/global_cell are positions in ascending user-id order, as the writers expect
  !> (equal to the global indices when the model keeps its arrays sorted by id).
  subroutine fill_output_mesh(decomp, x, node_id, topology, elem_id, elem_part_id, out)
    type(decomposition_t), intent(in) :: decomp   !< this rank's decomposition
    real(wp), intent(in) :: x(:,:)                !< (3,nnode) global reference coordinates
    integer, intent(in) :: node_id(:)             !< (nnode) user node ids
    integer, intent(in) :: topology(:)            !< (nelem) TOPO_* code of each element
    integer, intent(in) :: elem_id(:)             !< (nelem) user element ids
    integer, intent(in) :: elem_part_id(:)        !< (nelem) user part id of each element
    type(output_mesh_t), intent(out) :: out       !< this rank's output piece
    integer, allocatable :: position(:)

    out%nnode = decomp%nnode_local
    out%ncell = decomp%nelem_local
    out%nnode_global = decomp%nnode_global
    out%ncell_global = decomp%nelem_global

    out%x = x(:, decomp%node_global)
    out%node_id = node_id(decomp%node_global)
    call id_positions(node_id(1:decomp%nnode_global), position)
    out%global_node = position(decomp%node_global)
    out%node_owned = decomp%node_owned

    out%topology = topology(decomp%elem_global)
    out%cell_start = decomp%elem_start_local
    out%conn = decomp%elem_nodes_local
    out%cell_id = elem_id(decomp%elem_global)
    out%cell_part = elem_part_id(decomp%elem_global)
    call id_positions(elem_id(1:decomp%nelem_global), position)
    out%global_cell = position(decomp%elem_global)
  end subroutine fill_output_mesh

  !> Position of each entry in ascending id order (ties keep array order): the identity when
  !> the ids are already ascending, else a stable sort, O(n log n).
  subroutine id_positions(ids, position)
    integer, intent(in) :: ids(:)                         !< user ids
    integer, allocatable, intent(out) :: position(:)      !< 1-based rank of each id
    integer, allocatable :: order(:)
    integer :: i, n

    n = size(ids)
    allocate(position(n))
    position = [(i, i = 1, n)]
    if (n < 2) return
    if (all(ids(2:n) >= ids(1:n - 1))) return
    call stable_sort_order(ids, order)
    do i = 1, n
      position(order(i)) = i
    end do
  end subroutine id_positions

  !> Indices that sort keys ascending, stable (bottom-up merge sort).
  subroutine stable_sort_order(keys, order)
    integer, intent(in) :: keys(:)                        !< values to sort
    integer, allocatable, intent(out) :: order(:)         !< keys(order) is ascending
    integer, allocatable :: work(:)
    integer :: n, width, left, middle, right, i, j, k

    n = size(keys)
    allocate(work(n))
    order = [(i, i = 1, n)]
    width = 1
    do while (width < n)
      left = 1
      do while (left <= n)
        middle = min(left + width - 1, n)
        right = min(left + 2*width - 1, n)
        i = left
        j = middle + 1
        do k = left, right
          if (j > right) then
            work(k) = order(i)
            i = i + 1
          else if (i > middle) then
            work(k) = order(j)
            j = j + 1
          else if (keys(order(j)) < keys(order(i))) then
            work(k) = order(j)
            j = j + 1
          else
            work(k) = order(i)
            i = i + 1
          end if
        end do
        left = left + 2*width
      end do
      order = work
      width = 2*width
    end do
  end subroutine stable_sort_order

end module mefem_decomposition
