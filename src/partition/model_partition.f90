!> Splits the model over the ranks: METIS on rank 0 (dual graph of the elements), the
!> element-to-rank map broadcast, then each rank builds its own decomposition.
module mefem_model_partition
  use mefem_comm, only: comm_rank, comm_size, comm_is_root, comm_bcast
  use mefem_kinds, only: i8
  use mefem_errors, only: status_t, fatal
  use mefem_model, only: model_t, ELEM_SHELL
  use mefem_output_mesh, only: NODES_OF_TOPO
  use mefem_metis, only: metis_partition_elements
  use mefem_decomposition, only: decomposition_t, build_decomposition
  implicit none
  private

  public :: partition_model, element_csr

  integer, parameter :: MIN_CHUNKS = 64         !< chunks of any model with more elements
  integer, parameter :: ELEMENTS_PER_CHUNK = 4096   !< elements per chunk in larger models

contains

  !> Corner nodes of all elements in compressed rows (elem_start(e):elem_start(e+1)-1).
  subroutine element_csr(model, elem_start, elem_nodes)
    type(model_t), intent(in) :: model                  !< resolved model
    integer, allocatable, intent(out) :: elem_start(:)  !< (nelem+1) row starts
    integer, allocatable, intent(out) :: elem_nodes(:)  !< node indices
    integer :: e, nn
    associate (el => model%elements)
      allocate(elem_start(el%n + 1))
      elem_start(1) = 1
      do e = 1, el%n
        elem_start(e + 1) = elem_start(e) + NODES_OF_TOPO(el%topology(e))
      end do
      allocate(elem_nodes(elem_start(el%n + 1) - 1))
      do e = 1, el%n
        nn = NODES_OF_TOPO(el%topology(e))
        elem_nodes(elem_start(e):elem_start(e + 1) - 1) = el%conn(1:nn, e)
      end do
    end associate
  end subroutine element_csr

  !> Partition the elements over all ranks and build this rank's decomposition.
  !>
  !> Without element_chunk (implicit and linear analyses): METIS k-way into one part per
  !> rank. With it (the explicit solver): the elements are first cut into chunks that do not
  !> depend on the number of ranks (chunk_elements), and every rank gets a contiguous range of
  !> whole chunks; the explicit assembly sums per chunk, then over the chunks in ascending
  !> order (mefem_explicit_layout), which gives the same bits on any number of ranks up to the
  !> number of chunks.
  subroutine partition_model(model, decomp, element_rank, element_chunk)
    type(model_t), intent(in) :: model               !< resolved model
    type(decomposition_t), intent(out) :: decomp     !< this rank's share
    integer, allocatable, intent(out), optional :: element_rank(:) !< rank of every element
    integer, allocatable, intent(out), optional :: element_chunk(:) !< chunk of every element
    integer, allocatable :: elem_start(:), elem_nodes(:), elem_part(:), elem_chunk(:)
    type(status_t) :: status
    integer :: ncommon, nchunk
    call element_csr(model, elem_start, elem_nodes)
    allocate(elem_part(model%elements%n))
    elem_part = 0
    ! neighbours share an edge in 2D or when shells are present, a face otherwise
    ncommon = 3
    if (model%dimension == 2 .or. any(model%elements%keyword(1:model%elements%n) == ELEM_SHELL)) &
      ncommon = 2
    if (present(element_chunk)) then
      call chunk_elements(model, elem_start, elem_nodes, ncommon, elem_chunk, nchunk)
      call chunks_to_ranks(elem_chunk, nchunk, comm_size(), elem_part)
      call move_alloc(elem_chunk, element_chunk)
    else if (min(comm_size(), model%elements%n) > 1) then
      ! more ranks than elements: the elements on the first ranks, the others idle
      if (comm_is_root()) then
        call metis_partition_elements(model%elements%n, model%nodes%n, elem_start, elem_nodes, &
                                      ncommon, min(comm_size(), model%elements%n), &
                                      elem_part=elem_part, status=status)
      end if
      call check_partitioning(status)
      call comm_bcast(elem_part)
    end if
    call build_decomposition(comm_rank(), comm_size(), model%elements%n, model%nodes%n, &
                             elem_start, elem_nodes, elem_part, decomp)
    if (present(element_rank)) call move_alloc(elem_part, element_rank)
  end subroutine partition_model

  !> Number of chunks of a model of nelem elements run on nranks ranks: at least MIN_CHUNKS
  !> (so that runs on up to that many ranks give the same bits), one per ELEMENTS_PER_CHUNK
  !> elements in larger models, never fewer than the ranks, never more than the elements.
  pure integer function chunk_count(nelem, nranks)
    integer, intent(in) :: nelem                     !< elements of the model
    integer, intent(in) :: nranks                    !< ranks of the run
    chunk_count = min(nelem, max(MIN_CHUNKS, (nelem + ELEMENTS_PER_CHUNK - 1)/ELEMENTS_PER_CHUNK, &
                                 nranks))
  end function chunk_count

  !> The chunks of the explicit solver (0-based numbers, the same on every rank): METIS
  !> recursive bisection on rank 0 (contiguous ranges of chunks are compact pieces of the
  !> mesh), one chunk per element in models with at most chunk_count elements.
  subroutine chunk_elements(model, elem_start, elem_nodes, ncommon, elem_chunk, nchunk)
    type(model_t), intent(in) :: model               !< resolved model
    integer, intent(in) :: elem_start(:)             !< element_csr's row starts
    integer, intent(in) :: elem_nodes(:)             !< element_csr's nodes
    integer, intent(in) :: ncommon                   !< nodes neighbours share
    integer, allocatable, intent(out) :: elem_chunk(:) !< (nelem) chunk of every element
    integer, intent(out) :: nchunk                   !< number of chunks
    type(status_t) :: status
    integer :: nelem, e
    nelem = model%elements%n
    nchunk = chunk_count(nelem, comm_size())
    allocate(elem_chunk(nelem))
    if (nchunk == nelem) then
      elem_chunk = [(e - 1, e = 1, nelem)]
      return
    end if
    elem_chunk = 0
    if (comm_is_root()) call metis_partition_elements(nelem, model%nodes%n, elem_start, &
        elem_nodes, ncommon, nchunk, elem_part=elem_chunk, status=status, bisection=.true.)
    call check_partitioning(status)
    call comm_bcast(elem_chunk)
  end subroutine chunk_elements

  !> Contiguous ranges of chunks to the ranks, balanced by their element counts: a chunk goes
  !> to the rank whose share of the elements holds the chunk's middle element.
  subroutine chunks_to_ranks(elem_chunk, nchunk, nranks, elem_part)
    integer, intent(in) :: elem_chunk(:)             !< (nelem) chunk of every element
    integer, intent(in) :: nchunk                    !< number of chunks
    integer, intent(in) :: nranks                    !< number of ranks
    integer, intent(out) :: elem_part(:)             !< (nelem) rank of every element
    integer(i8) :: weight(0:max(nchunk, 1) - 1), before, total
    integer :: chunk_rank(0:max(nchunk, 1) - 1), k
    weight = 0
    do k = 1, size(elem_chunk)
      weight(elem_chunk(k)) = weight(elem_chunk(k)) + 1
    end do
    total = max(sum(weight), 1_i8)
    before = 0
    do k = 0, nchunk - 1
      chunk_rank(k) = int(min(int(nranks - 1, i8), ((2*before + weight(k))*nranks)/(2*total)))
      before = before + weight(k)
    end do
    elem_part = chunk_rank(elem_chunk)
  end subroutine chunks_to_ranks

  !> Stop every rank if the partitioning on rank 0 failed.
  subroutine check_partitioning(status)
    type(status_t), intent(in) :: status             !< rank 0's result
    logical :: ok
    ok = status%ok
    call comm_bcast(ok)
    if (.not. ok) then
      if (comm_is_root()) call fatal('partitioning failed: '//status%message)
      call fatal('partitioning failed')
    end if
  end subroutine check_partitioning

end module mefem_model_partition
