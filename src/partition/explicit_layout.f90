!> One rank's share of the integration cells and of all nodes (mesh and enriched) for the
!> explicit solver, built from the decomposition, the global element partition and the cells.
!>
!> Who computes what:
!> - cell c is computed by the rank of its first element, cells%elements(1,c);
!> - this rank's local nodes are every node (mesh nodes 1..n_mesh_nodes, enriched nodes after
!>   them, as numbered by mefem_cells) touched by its own elements (their corners and, for
!>   ME-FEM elements, their enriched nodes), by the cells it computes, plus the decomposition's
!>   local nodes (rank 0 keeps nodes no element touches). A cell of a face between elements of
!>   two ranks therefore brings the far corner and the enriched node of the other element in;
!> - owner of a mesh node: the decomposition's rule, the lowest rank whose elements touch it;
!>   owner of an enriched node: the rank of its element (which always has it locally);
!> - nodes p and q both hold locally are shared between p and q; each rank's list for the
!>   other names them in ascending global order, so both sides agree without matching.
!> Every rank can work out every other rank's node set from the global data, so nothing is
!> communicated here; the work per rank is linear in the global mesh plus the number of ranks.
!>
!> Order-fixed assembly (what makes forces bit-identical for any number of ranks): the force of
!> a cell on its j-th node is its "contribution" (c, j). The cells are grouped into chunks
!> that do not depend on the number of ranks (mefem_model_partition: the chunk of a cell is
!> its first element's; every rank computes whole chunks). The nodal force at node n is
!>   f(n) = S(n, k1) + S(n, k2) + ...   (added left to right, chunks k1 < k2 < ... touching n)
!> where S(n, k) is the sum of chunk k's contributions to n in ascending global cell order.
!> The rank of chunk k computes S(n, k) in its cell loop into a "target" column of its nodal
!> arrays: node n's own column when k is the only chunk touching n, otherwise an extra
!> "partial" column after the nodes; the ranks that hold n and not chunk k receive S(n, k)
!> (one value per node and chunk, not the contributions), and every rank holding n adds the
!> S(n, k) in chunk order ("combine"). This module lists, per own contribution, its target
!> column; per combined node, where each S(n, k) is found (a partial column or a received
!> position); per neighbour, the columns sent, node by node of the shared list and chunk by
!> chunk, which the receiver derives in the same order from the global data. The exchange
!> itself is mefem_halo's halo_assemble.
module mefem_explicit_layout
  use mefem_errors, only: status_t, fatal_local
  use mefem_decomposition, only: decomposition_t
  use mefem_cells, only: cells_t, CELL_MAX_NODES
  use mefem_index_lists, only: counts_to_starts
  implicit none
  private

  public :: explicit_layout_build, explicit_layout_local_node, explicit_layout_release_plan

  !> This rank's cells and nodes, ownership, halo lists and the order-fixed assembly plan.
  type, public :: explicit_layout_t
    integer :: rank = 0                           !< this rank (0-based)
    integer :: nranks = 1                         !< number of ranks
    integer :: n_mesh_nodes = 0                   !< mesh nodes in the global model
    integer :: nnode_global = 0                   !< mesh + enriched nodes in the global model
    integer :: ncell_global = 0                   !< cells in the global model
    integer :: slots = CELL_MAX_NODES             !< contribution slots per cell
    ! cells this rank computes
    integer :: ncell_local = 0                    !< cells computed by this rank
    integer, allocatable :: cell_global(:)        !< (ncell_local) global cell indices, ascending
    integer, allocatable :: cell_nodes(:,:)       !< (slots, ncell_local) local node of each
                                                  !< node of the cell (cells%nodes order), 0 past
                                                  !< cells%nnodes
    ! nodes
    integer :: nnode_local = 0                    !< mesh and enriched nodes held by this rank
    integer :: nnode_owned = 0                    !< local nodes this rank owns
    integer, allocatable :: node_global(:)        !< (nnode_local) global node, ascending
                                                  !< (enriched nodes come after mesh nodes)
    integer, allocatable :: node_owner(:)         !< (nnode_local) owning rank
    logical, allocatable :: node_owned(:)         !< (nnode_local) node_owner == rank
    ! halo pattern (same meaning as in decomposition_t)
    integer :: nneighbour = 0                     !< ranks sharing at least one node with us
    integer, allocatable :: neighbour_rank(:)     !< (nneighbour) their ranks, ascending
    integer, allocatable :: shared_start(:)       !< (nneighbour+1) neighbour k's nodes are at
                                                  !< shared_start(k):shared_start(k+1)-1
    integer, allocatable :: shared_nodes(:)       !< local nodes, ascending per neighbour
    ! order-fixed assembly plan
    integer :: npartial = 0                       !< partial columns (after the nnode_local
                                                  !< node columns)
    integer :: ntarget = 0                        !< nnode_local + npartial
    integer, allocatable :: cell_target(:,:)      !< (slots, ncell_local) target column of each
                                                  !< own contribution (0 past cells%nnodes)
    integer, allocatable :: combine_node(:)       !< local nodes summed over their chunks
    integer, allocatable :: combine_start(:)      !< (size(combine_node)+1) node m adds the
    integer, allocatable :: combine_source(:)     !< sources combine_start(m):combine_start(m+1)
                                                  !< -1 in this (ascending chunk) order: > 0 a
                                                  !< target column, < 0 -(position in the
                                                  !< concatenated receive buffer)
    integer, allocatable :: send_start(:)         !< (nneighbour+1) offsets into send_source
    integer, allocatable :: send_source(:)        !< target columns sent to neighbour k, in
                                                  !< order
    integer, allocatable :: receive_start(:)      !< (nneighbour+1) neighbour k's values are
                                                  !< receive_start(k):receive_start(k+1)-1
    ! output plan: the cell results the means of this rank's output piece read (the cells of
    ! its elements and the cells touching its elements' nodes), gathered from the ranks that
    ! compute them (mefem_halo's halo_gather_cell_results)
    integer, allocatable :: result_cell(:)        !< global cells the piece reads, ascending
    integer, allocatable :: result_source(:)      !< (size(result_cell)) > 0: local cell; < 0:
                                                  !< -(position in the received results)
    integer, allocatable :: result_send_start(:)  !< (0:nranks) rank r's cells are result_send_
                                                  !< cell(result_send_start(r)+1:result_send_
                                                  !< start(r+1))
    integer, allocatable :: result_send_cell(:)   !< local cells sent, ascending per rank
    integer, allocatable :: result_receive_start(:) !< (0:nranks) rank r's results are positions
                                                  !< result_receive_start(r)+1 .. (r+1) of the
                                                  !< received results
  end type explicit_layout_t

contains

  !> Build this rank's explicit layout. elem_part, elem_start and elem_nodes are the global
  !> element partition and corner connectivity that built decomp (model_partition's
  !> element_csr), elem_chunk the chunks of the assembly (every chunk's elements on one rank).
  !> Inconsistent input sets status (or, without status, stops with a message).
  subroutine explicit_layout_build(decomp, elem_part, elem_chunk, elem_start, elem_nodes, &
                                   cells, layout, status)
    type(decomposition_t), intent(in) :: decomp       !< this rank's decomposition
    integer, intent(in) :: elem_part(:)               !< (nelem) rank of every element
    integer, intent(in) :: elem_chunk(:)              !< (nelem) chunk of every element (>= 0)
    integer, intent(in) :: elem_start(:)              !< (nelem+1) element starts
    integer, intent(in) :: elem_nodes(:)              !< 1-based global mesh node indices
    type(cells_t), intent(in) :: cells                !< all cells of the model
    type(explicit_layout_t), intent(out) :: layout    !< the result
    type(status_t), intent(out), optional :: status   !< failure and its reason
    integer, allocatable :: cell_rank(:), cell_chunk(:), node_rank_start(:), node_ranks(:)
    integer, allocatable :: global_to_local(:)
    type(status_t) :: check_status
    integer :: c

    call check_layout_input(decomp, elem_part, elem_chunk, elem_start, elem_nodes, cells, &
                            check_status)
    if (present(status)) status = check_status
    if (.not. check_status%ok) then
      if (present(status)) return
      call fatal_local(check_status%message)
    end if

    layout%rank = decomp%rank
    layout%nranks = decomp%nranks
    layout%n_mesh_nodes = decomp%nnode_global
    layout%nnode_global = decomp%nnode_global + cells%n_enriched
    layout%ncell_global = cells%n

    allocate(cell_rank(cells%n), cell_chunk(cells%n))
    do c = 1, cells%n
      cell_rank(c) = elem_part(cells%elements(1, c))
      cell_chunk(c) = elem_chunk(cells%elements(1, c))
    end do
    call collect_node_ranks(layout, elem_part, elem_start, elem_nodes, cells, cell_rank, &
                            node_rank_start, node_ranks)
    call select_local_nodes(layout, elem_part, elem_start, elem_nodes, cells, node_rank_start, &
                            node_ranks, global_to_local)
    call build_shared_lists(layout, node_rank_start, node_ranks)
    call select_local_cells(layout, cells, cell_rank, global_to_local)
    call build_assembly_plan(layout, cells, cell_rank, cell_chunk)
    call collect_node_ranks(layout, elem_part, elem_start, elem_nodes, cells, cell_rank, &
                            node_rank_start, node_ranks, with_cells=.false.)
    call build_result_plan(layout, elem_part, cells, cell_rank, node_rank_start, node_ranks)
  end subroutine explicit_layout_build

  !> Local index of global node `global` (mesh or enriched numbering), 0 if not local.
  pure integer function explicit_layout_local_node(layout, global) result(local)
    type(explicit_layout_t), intent(in) :: layout   !< this rank's layout
    integer, intent(in) :: global                   !< global node index
    integer :: low, high, middle
    local = 0
    low = 1
    high = layout%nnode_local
    do while (low <= high)
      middle = (low + high)/2
      if (layout%node_global(middle) == global) then
        local = middle
        return
      else if (layout%node_global(middle) < global) then
        low = middle + 1
      else
        high = middle - 1
      end if
    end do
  end function explicit_layout_local_node

  !> Free what only the set-up reads (the cells' lists and nodes, the assembly plan and its
  !> send and receive lists: the halo and the solver's state keep their own copies); the
  !> nodes and the output plan stay, for the outputs.
  subroutine explicit_layout_release_plan(layout)
    type(explicit_layout_t), intent(inout) :: layout  !< a built layout
    if (allocated(layout%cell_global)) deallocate(layout%cell_global)
    if (allocated(layout%cell_nodes)) deallocate(layout%cell_nodes)
    if (allocated(layout%cell_target)) deallocate(layout%cell_target)
    if (allocated(layout%combine_node)) deallocate(layout%combine_node)
    if (allocated(layout%combine_start)) deallocate(layout%combine_start)
    if (allocated(layout%combine_source)) deallocate(layout%combine_source)
    if (allocated(layout%send_start)) deallocate(layout%send_start)
    if (allocated(layout%send_source)) deallocate(layout%send_source)
    if (allocated(layout%receive_start)) deallocate(layout%receive_start)
  end subroutine explicit_layout_release_plan

  !> Sizes and ranges that must agree between the decomposition, the partition and the cells.
  subroutine check_layout_input(decomp, elem_part, elem_chunk, elem_start, elem_nodes, cells, &
                                status)
    type(decomposition_t), intent(in) :: decomp       !< this rank's decomposition
    integer, intent(in) :: elem_part(:)               !< rank of every element
    integer, intent(in) :: elem_chunk(:)              !< chunk of every element
    integer, intent(in) :: elem_start(:)              !< element starts
    integer, intent(in) :: elem_nodes(:)              !< global node indices
    type(cells_t), intent(in) :: cells                !< all cells
    type(status_t), intent(inout) :: status           !< set on failure
    character(len=200) :: text
    integer :: nelem

    nelem = decomp%nelem_global
    text = ''
    if (size(elem_part) < nelem .or. size(elem_chunk) < nelem .or. &
        size(elem_start) < nelem + 1) then
      write(text, '(a,i0,a)') 'elem_part/elem_chunk/elem_start are shorter than the ', nelem, &
          ' elements of the decomposition'
    else if (cells%n_mesh_nodes /= decomp%nnode_global) then
      write(text, '(a,i0,a,i0,a)') 'the cells know ', cells%n_mesh_nodes, &
          ' mesh nodes, the decomposition ', decomp%nnode_global
    else if (size(cells%enriched_of) /= nelem) then
      write(text, '(a,i0,a,i0,a)') 'the cells know ', size(cells%enriched_of), &
          ' elements, the decomposition ', nelem
    else if (elem_start(nelem + 1) - 1 > size(elem_nodes)) then
      text = 'elem_nodes is shorter than elem_start says'
    end if
    if (len_trim(text) == 0 .and. nelem > 0) then
      if (any(elem_part(1:nelem) < 0 .or. elem_part(1:nelem) >= decomp%nranks)) then
        text = 'an element part is outside 0..nranks-1'
      else if (any(elem_chunk(1:nelem) < 0)) then
        text = 'an element chunk is negative'
      else if (.not. whole_chunks(elem_part(1:nelem), elem_chunk(1:nelem))) then
        text = 'a chunk''s elements are on more than one rank'
      else if (decomp%nelem_local > 0) then
        if (any(elem_part(decomp%elem_global) /= decomp%rank)) &
          text = 'elem_part does not match the decomposition'' elements'
      end if
    end if
    if (len_trim(text) == 0 .and. cells%n > 0) then
      if (any(cells%elements(1, 1:cells%n) < 1 .or. cells%elements(1, 1:cells%n) > nelem)) &
        text = 'a cell has no first element'
    end if
    if (len_trim(text) > 0) then
      status%ok = .false.
      status%message = 'explicit_layout_build: '//trim(text)
    end if
  end subroutine check_layout_input

  !> Counting sort of items by rank: rank r's items, ascending, are
  !> items(bucket_start(r)+1:bucket_start(r+1)).
  pure subroutine bucket_by_rank(nranks, item_rank, bucket_start, items)
    integer, intent(in) :: nranks                         !< number of ranks
    integer, intent(in) :: item_rank(:)                   !< rank of each item
    integer, allocatable, intent(out) :: bucket_start(:)  !< (0:nranks) offsets
    integer, allocatable, intent(out) :: items(:)         !< items sorted by rank
    integer, allocatable :: next(:)
    integer :: i, r
    allocate(bucket_start(0:nranks), next(0:nranks - 1), items(size(item_rank)))
    bucket_start = 0
    do i = 1, size(item_rank)
      bucket_start(item_rank(i) + 1) = bucket_start(item_rank(i) + 1) + 1
    end do
    do r = 1, nranks
      bucket_start(r) = bucket_start(r) + bucket_start(r - 1)
    end do
    next = bucket_start(0:nranks - 1)
    do i = 1, size(item_rank)
      next(item_rank(i)) = next(item_rank(i)) + 1
      items(next(item_rank(i))) = i
    end do
  end subroutine bucket_by_rank

  !> For every node (mesh and enriched), the ranks holding it, ascending and without repeats:
  !> node n's ranks are node_ranks(node_rank_start(n):node_rank_start(n+1)-1). Ranks are
  !> visited in ascending order, one pass to count and one to fill.
  subroutine collect_node_ranks(layout, elem_part, elem_start, elem_nodes, cells, cell_rank, &
                                node_rank_start, node_ranks, with_cells)
    type(explicit_layout_t), intent(in) :: layout         !< sizes
    integer, intent(in) :: elem_part(:)                   !< rank of every element
    integer, intent(in) :: elem_start(:)                  !< element starts
    integer, intent(in) :: elem_nodes(:)                  !< global mesh node indices
    type(cells_t), intent(in) :: cells                    !< all cells
    integer, intent(in) :: cell_rank(:)                   !< rank computing each cell
    integer, allocatable, intent(out) :: node_rank_start(:) !< (nnode_global+1) offsets
    integer, allocatable, intent(out) :: node_ranks(:)    !< ranks holding each node
    logical, intent(in), optional :: with_cells           !< .false.: only the ranks whose
                                                          !< elements touch it (output pieces)
    integer, allocatable :: elem_bucket_start(:), elem_bucket(:), cell_bucket_start(:)
    integer, allocatable :: cell_bucket(:), last_rank(:), next(:)
    logical, allocatable :: touched(:)
    logical :: count_cells
    integer :: nelem, nall, pass, r, k, e, c, j, n

    nelem = size(cells%enriched_of)
    nall = layout%nnode_global
    call bucket_by_rank(layout%nranks, elem_part(1:nelem), elem_bucket_start, elem_bucket)
    count_cells = .true.
    if (present(with_cells)) count_cells = with_cells
    if (count_cells) then
      call bucket_by_rank(layout%nranks, cell_rank, cell_bucket_start, cell_bucket)
    else
      call bucket_by_rank(layout%nranks, [integer ::], cell_bucket_start, cell_bucket)
    end if
    allocate(touched(layout%n_mesh_nodes))
    touched = .false.
    touched(elem_nodes(1:elem_start(nelem + 1) - 1)) = .true.

    allocate(node_rank_start(nall + 1), last_rank(nall), next(nall))
    do pass = 1, 2
      last_rank = -1
      if (pass == 1) then
        next = 0
      else
        node_rank_start(1) = 1
        do n = 1, nall
          node_rank_start(n + 1) = node_rank_start(n) + next(n)
        end do
        allocate(node_ranks(node_rank_start(nall + 1) - 1))
        next = node_rank_start(1:nall)
      end if
      do r = 0, layout%nranks - 1
        if (r == 0) then
          do n = 1, layout%n_mesh_nodes
            if (.not. touched(n)) call mark(n, r)
          end do
        end if
        do k = elem_bucket_start(r) + 1, elem_bucket_start(r + 1)
          e = elem_bucket(k)
          do j = elem_start(e), elem_start(e + 1) - 1
            call mark(elem_nodes(j), r)
          end do
          if (cells%enriched_of(e) > 0) call mark(cells%enriched_of(e), r)
        end do
        do k = cell_bucket_start(r) + 1, cell_bucket_start(r + 1)
          c = cell_bucket(k)
          do j = 1, cells%nnodes(c)
            call mark(cells%nodes(j, c), r)
          end do
        end do
      end do
    end do

  contains

    !> Record rank r for node n once (count in pass 1, store in pass 2).
    subroutine mark(n, r)
      integer, intent(in) :: n   !< node
      integer, intent(in) :: r   !< rank
      if (last_rank(n) == r) return
      last_rank(n) = r
      if (pass == 2) node_ranks(next(n)) = r
      next(n) = next(n) + 1
    end subroutine mark

  end subroutine collect_node_ranks

  !> This rank's nodes (ascending global order), their owners and the global-to-local map.
  subroutine select_local_nodes(layout, elem_part, elem_start, elem_nodes, cells, &
                                node_rank_start, node_ranks, global_to_local)
    type(explicit_layout_t), intent(inout) :: layout      !< rank in, nodes out
    integer, intent(in) :: elem_part(:)                   !< rank of every element
    integer, intent(in) :: elem_start(:)                  !< element starts
    integer, intent(in) :: elem_nodes(:)                  !< global mesh node indices
    type(cells_t), intent(in) :: cells                    !< all cells
    integer, intent(in) :: node_rank_start(:)             !< (nnode_global+1) offsets
    integer, intent(in) :: node_ranks(:)                  !< ranks holding each node
    integer, allocatable, intent(out) :: global_to_local(:) !< (nnode_global) local or 0
    integer, allocatable :: owner(:)
    integer :: nelem, nall, n, e, j, nlocal

    nelem = size(cells%enriched_of)
    nall = layout%nnode_global
    ! owner: lowest rank whose elements touch a mesh node (0 if none), element's rank for an
    ! enriched node
    allocate(owner(nall))
    owner = layout%nranks
    do e = 1, nelem
      do j = elem_start(e), elem_start(e + 1) - 1
        owner(elem_nodes(j)) = min(owner(elem_nodes(j)), elem_part(e))
      end do
      if (cells%enriched_of(e) > 0) owner(cells%enriched_of(e)) = elem_part(e)
    end do
    where (owner == layout%nranks) owner = 0

    allocate(global_to_local(nall))
    global_to_local = 0
    nlocal = 0
    do n = 1, nall
      if (any(node_ranks(node_rank_start(n):node_rank_start(n + 1) - 1) == layout%rank)) then
        nlocal = nlocal + 1
        global_to_local(n) = nlocal
      end if
    end do
    layout%nnode_local = nlocal
    allocate(layout%node_global(nlocal))
    do n = 1, nall
      if (global_to_local(n) > 0) layout%node_global(global_to_local(n)) = n
    end do
    layout%node_owner = owner(layout%node_global)
    layout%node_owned = layout%node_owner == layout%rank
    layout%nnode_owned = count(layout%node_owned)
  end subroutine select_local_nodes

  !> Neighbour ranks and the local nodes shared with each, ascending in global order.
  subroutine build_shared_lists(layout, node_rank_start, node_ranks)
    type(explicit_layout_t), intent(inout) :: layout      !< local nodes in, halo lists out
    integer, intent(in) :: node_rank_start(:)             !< (nnode_global+1) offsets
    integer, intent(in) :: node_ranks(:)                  !< ranks holding each node
    integer, allocatable :: shared_count(:), neighbour_of_rank(:), next(:)
    integer :: i, n, j, q, k

    allocate(shared_count(0:layout%nranks - 1), neighbour_of_rank(0:layout%nranks - 1))
    shared_count = 0
    do i = 1, layout%nnode_local
      n = layout%node_global(i)
      do j = node_rank_start(n), node_rank_start(n + 1) - 1
        q = node_ranks(j)
        if (q /= layout%rank) shared_count(q) = shared_count(q) + 1
      end do
    end do
    layout%nneighbour = count(shared_count > 0)
    allocate(layout%neighbour_rank(layout%nneighbour), layout%shared_start(layout%nneighbour + 1))
    neighbour_of_rank = 0
    layout%shared_start(1) = 1
    k = 0
    do q = 0, layout%nranks - 1
      if (shared_count(q) == 0) cycle
      k = k + 1
      layout%neighbour_rank(k) = q
      neighbour_of_rank(q) = k
      layout%shared_start(k + 1) = layout%shared_start(k) + shared_count(q)
    end do
    allocate(layout%shared_nodes(layout%shared_start(layout%nneighbour + 1) - 1))
    allocate(next(layout%nneighbour))
    next = layout%shared_start(1:layout%nneighbour)
    do i = 1, layout%nnode_local
      n = layout%node_global(i)
      do j = node_rank_start(n), node_rank_start(n + 1) - 1
        q = node_ranks(j)
        if (q == layout%rank) cycle
        k = neighbour_of_rank(q)
        layout%shared_nodes(next(k)) = i
        next(k) = next(k) + 1
      end do
    end do
  end subroutine build_shared_lists

  !> The cells this rank computes and their local nodes.
  subroutine select_local_cells(layout, cells, cell_rank, global_to_local)
    type(explicit_layout_t), intent(inout) :: layout      !< nodes in, cells out
    type(cells_t), intent(in) :: cells                    !< all cells
    integer, intent(in) :: cell_rank(:)                   !< rank computing each cell
    integer, intent(in) :: global_to_local(:)             !< (nnode_global) local or 0
    integer :: c, l, j

    layout%ncell_local = count(cell_rank == layout%rank)
    allocate(layout%cell_global(layout%ncell_local))
    allocate(layout%cell_nodes(layout%slots, layout%ncell_local))
    layout%cell_nodes = 0
    l = 0
    do c = 1, cells%n
      if (cell_rank(c) /= layout%rank) cycle
      l = l + 1
      layout%cell_global(l) = c
      do j = 1, cells%nnodes(c)
        layout%cell_nodes(j, l) = global_to_local(cells%nodes(j, c))
      end do
    end do
  end subroutine select_local_cells

  !> Every chunk's elements on one rank.
  pure logical function whole_chunks(elem_part, elem_chunk)
    integer, intent(in) :: elem_part(:)               !< rank of every element
    integer, intent(in) :: elem_chunk(:)              !< chunk (>= 0) of every element
    integer :: chunk_rank(0:max(0, maxval(elem_chunk)))
    integer :: e
    chunk_rank = -1
    whole_chunks = .true.
    do e = 1, size(elem_part)
      if (chunk_rank(elem_chunk(e)) == -1) chunk_rank(elem_chunk(e)) = elem_part(e)
      if (chunk_rank(elem_chunk(e)) /= elem_part(e)) whole_chunks = .false.
    end do
  end function whole_chunks

  !> The order-fixed assembly plan (see the module's header): the target column of every own
  !> contribution, the combined nodes' sources in ascending chunk order, and per neighbour
  !> the columns sent and the count received (node by node of the shared list, chunk by chunk).
  subroutine build_assembly_plan(layout, cells, cell_rank, cell_chunk)
    type(explicit_layout_t), intent(inout) :: layout      !< cells, nodes and halo lists in
    type(cells_t), intent(in) :: cells                    !< all cells
    integer, intent(in) :: cell_rank(:)                   !< rank computing each cell
    integer, intent(in) :: cell_chunk(:)                  !< chunk of each cell
    integer, allocatable :: touch_start(:), touch_cell(:), next(:)
    integer, allocatable :: chunk_start(:), chunk_of(:), chunk_source(:), node_chunks(:)
    integer, allocatable :: chunk_rank(:)
    integer :: nall, c, j, n, i, k, s, q, m, position, nsend, nchunk_node, l, chunk, pass
    integer :: nchunk_total, column

    ! node -> cells touching it over the whole model, ascending
    nall = layout%nnode_global
    allocate(touch_start(nall + 1), next(nall))
    touch_start = 0
    do c = 1, cells%n
      do j = 1, cells%nnodes(c)
        touch_start(cells%nodes(j, c) + 1) = touch_start(cells%nodes(j, c) + 1) + 1
      end do
    end do
    touch_start(1) = 1
    do n = 1, nall
      touch_start(n + 1) = touch_start(n + 1) + touch_start(n)
    end do
    allocate(touch_cell(touch_start(nall + 1) - 1))
    next = touch_start(1:nall)
    do c = 1, cells%n
      do j = 1, cells%nnodes(c)
        n = cells%nodes(j, c)
        touch_cell(next(n)) = c
        next(n) = next(n) + 1
      end do
    end do

    allocate(chunk_rank(0:max(0, maxval(cell_chunk))))
    chunk_rank = -1
    do c = 1, cells%n                       ! (every chunk's cells are on one rank)
      chunk_rank(cell_chunk(c)) = cell_rank(c)
    end do

    ! per local node, the chunks touching it (ascending) and where each S(n, k) is: its own
    ! column (the only chunk, this rank's), a new partial column (this rank's chunk), or a
    ! receive position (filled below; 0 until then)
    allocate(chunk_start(layout%nnode_local + 1), node_chunks(32))
    do pass = 1, 2
      if (pass == 2) then
        allocate(chunk_of(chunk_start(layout%nnode_local + 1) - 1), &
                 chunk_source(chunk_start(layout%nnode_local + 1) - 1))
        chunk_source = 0
      end if
      chunk_start(1) = 1
      layout%npartial = 0
      do i = 1, layout%nnode_local
        call chunks_of_node(layout%node_global(i))
        chunk_start(i + 1) = chunk_start(i) + nchunk_node
        if (pass == 1) cycle
        chunk_of(chunk_start(i):chunk_start(i + 1) - 1) = node_chunks(1:nchunk_node)
        do k = 1, nchunk_node
          if (chunk_rank(node_chunks(k)) /= layout%rank) cycle
          if (nchunk_node == 1) then
            chunk_source(chunk_start(i)) = i
          else
            layout%npartial = layout%npartial + 1
            chunk_source(chunk_start(i) + k - 1) = layout%nnode_local + layout%npartial
          end if
        end do
      end do
    end do
    layout%ntarget = layout%nnode_local + layout%npartial

    ! the exchange: neighbour q's S(n, k) of its chunks, and ours for it, node by node of the
    ! shared list, chunk by chunk
    allocate(layout%receive_start(layout%nneighbour + 1), layout%send_start(layout%nneighbour + 1))
    layout%receive_start(1) = 1
    layout%send_start(1) = 1
    position = 0
    nsend = 0
    do pass = 1, 2
      if (pass == 2) allocate(layout%send_source(nsend))
      position = 0
      nsend = 0
      do k = 1, layout%nneighbour
        q = layout%neighbour_rank(k)
        do s = layout%shared_start(k), layout%shared_start(k + 1) - 1
          i = layout%shared_nodes(s)
          do m = chunk_start(i), chunk_start(i + 1) - 1
            if (chunk_rank(chunk_of(m)) == q) then
              position = position + 1
              if (pass == 2) chunk_source(m) = -position
            else if (chunk_rank(chunk_of(m)) == layout%rank) then
              nsend = nsend + 1
              if (pass == 2) layout%send_source(nsend) = chunk_source(m)
            end if
          end do
        end do
        layout%receive_start(k + 1) = position + 1
        layout%send_start(k + 1) = nsend + 1
      end do
    end do
    if (any(chunk_source == 0)) call fatal_local('explicit_layout_build: a chunk touching a '// &
        'local node is computed by a rank that does not share the node')

    ! the combined nodes: all but those whose only chunk is this rank's
    nchunk_total = 0
    m = 0
    do i = 1, layout%nnode_local
      if (chunk_start(i + 1) == chunk_start(i)) cycle
      if (chunk_source(chunk_start(i)) == i) cycle
      m = m + 1
      nchunk_total = nchunk_total + chunk_start(i + 1) - chunk_start(i)
    end do
    allocate(layout%combine_node(m), layout%combine_start(m + 1), &
             layout%combine_source(nchunk_total))
    layout%combine_start(1) = 1
    m = 0
    do i = 1, layout%nnode_local
      if (chunk_start(i + 1) == chunk_start(i)) cycle
      if (chunk_source(chunk_start(i)) == i) cycle
      m = m + 1
      layout%combine_node(m) = i
      layout%combine_start(m + 1) = layout%combine_start(m) + chunk_start(i + 1) - chunk_start(i)
      layout%combine_source(layout%combine_start(m):layout%combine_start(m + 1) - 1) = &
          chunk_source(chunk_start(i):chunk_start(i + 1) - 1)
    end do

    ! the target of every own contribution: the column of its node's S(n, chunk of the cell)
    allocate(layout%cell_target(layout%slots, layout%ncell_local))
    layout%cell_target = 0
    do l = 1, layout%ncell_local
      c = layout%cell_global(l)
      chunk = cell_chunk(c)
      do j = 1, cells%nnodes(c)
        i = layout%cell_nodes(j, l)
        column = 0
        do m = chunk_start(i), chunk_start(i + 1) - 1
          if (chunk_of(m) == chunk) then
            column = chunk_source(m)
            exit
          end if
        end do
        if (column <= 0) call fatal_local('explicit_layout_build: a contribution has no column')
        layout%cell_target(j, l) = column
      end do
    end do

  contains

    !> node_chunks(1:nchunk_node): the chunks of the cells touching global node n, ascending.
    subroutine chunks_of_node(n)
      integer, intent(in) :: n                    !< global node
      integer :: t, chunk_t, p
      nchunk_node = 0
      do t = touch_start(n), touch_start(n + 1) - 1
        chunk_t = cell_chunk(touch_cell(t))
        if (any(node_chunks(1:nchunk_node) == chunk_t)) cycle
        if (nchunk_node == size(node_chunks)) node_chunks = [node_chunks, node_chunks]
        p = nchunk_node                           ! insertion, ascending
        do while (p > 0)
          if (node_chunks(p) < chunk_t) exit
          node_chunks(p + 1) = node_chunks(p)
          p = p - 1
        end do
        node_chunks(p + 1) = chunk_t
        nchunk_node = nchunk_node + 1
      end do
    end subroutine chunks_of_node

  end subroutine build_assembly_plan

  !> The output plan (layout%result_*): a cell's results go to the ranks of its elements and
  !> to every rank whose elements touch one of its mesh nodes (node_ranks without the cells'
  !> ranks), the ranks whose output piece's means read it. Every rank applies this rule to the
  !> same global data, so what one sends is what the other expects; both lists are in
  !> ascending global cell order.
  subroutine build_result_plan(layout, elem_part, cells, cell_rank, node_rank_start, node_ranks)
    type(explicit_layout_t), intent(inout) :: layout      !< local cells in, output plan out
    integer, intent(in) :: elem_part(:)                   !< rank of every element
    type(cells_t), intent(in) :: cells                    !< all cells
    integer, intent(in) :: cell_rank(:)                   !< rank computing each cell
    integer, intent(in) :: node_rank_start(:)             !< (nnode_global+1) offsets
    integer, intent(in) :: node_ranks(:)                  !< ranks whose elements touch a node
    integer, allocatable :: readers(:), send_next(:), receive_next(:)
    logical, allocatable :: listed(:)
    integer :: nranks, nreaders, c, l, k, pass, r, nresult
    nranks = layout%nranks
    allocate(listed(0:nranks - 1), readers(nranks), send_next(0:nranks - 1), &
             receive_next(0:nranks - 1))
    listed = .false.
    allocate(layout%result_send_start(0:nranks), layout%result_receive_start(0:nranks))
    do pass = 1, 2
      ! this rank's cells, to the other ranks that read them
      if (pass == 1) then
        send_next = 0
      else
        call counts_to_starts(send_next, layout%result_send_start, 0)
        allocate(layout%result_send_cell(layout%result_send_start(nranks)))
      end if
      do l = 1, layout%ncell_local
        call cell_readers(layout%cell_global(l))
        do k = 1, nreaders
          r = readers(k)
          if (r == layout%rank) cycle
          send_next(r) = send_next(r) + 1
          if (pass == 2) layout%result_send_cell(send_next(r)) = l
        end do
      end do
      ! the cells this rank reads, from the ranks that compute them
      if (pass == 1) then
        receive_next = 0
      else
        call counts_to_starts(receive_next, layout%result_receive_start, 0)
        allocate(layout%result_cell(nresult), layout%result_source(nresult))
      end if
      nresult = 0
      l = 0
      do c = 1, cells%n
        if (cell_rank(c) == layout%rank) l = l + 1
        call cell_readers(c)
        if (.not. any(readers(1:nreaders) == layout%rank)) cycle
        nresult = nresult + 1
        r = cell_rank(c)
        if (r /= layout%rank) receive_next(r) = receive_next(r) + 1
        if (pass == 1) cycle
        layout%result_cell(nresult) = c
        if (r == layout%rank) then
          layout%result_source(nresult) = l
        else
          layout%result_source(nresult) = -receive_next(r)
        end if
      end do
    end do
  contains

    !> readers(1:nreaders): the ranks that read cell c's results, without repeats.
    subroutine cell_readers(c)
      integer, intent(in) :: c                    !< global cell
      integer :: slot, j, n, m
      nreaders = 0
      do slot = 1, 2
        if (cells%elements(slot, c) > 0) call add(elem_part(cells%elements(slot, c)))
      end do
      do j = 1, cells%nnodes(c)
        n = cells%nodes(j, c)
        if (n > cells%n_mesh_nodes) cycle
        do m = node_rank_start(n), node_rank_start(n + 1) - 1
          call add(node_ranks(m))
        end do
      end do
      listed(readers(1:nreaders)) = .false.
    end subroutine cell_readers

    !> Add rank r to readers once.
    subroutine add(r)
      integer, intent(in) :: r                    !< rank
      if (listed(r)) return
      listed(r) = .true.
      nreaders = nreaders + 1
      readers(nreaders) = r
    end subroutine add

  end subroutine build_result_plan

end module mefem_explicit_layout
