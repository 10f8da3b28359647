!> Splits the model over the ranks: METIS on rank 0 (dual graph of the elements), the
!> element-to-rank map broadcast, then each rank builds its own decomposition.
module mefem_model_partition
  use mefem_comm, only: comm_rank, comm_size, comm_is_root, comm_bcast
  use mefem_errors, only: status_t, fatal
  use mefem_model, only: model_t, ELEM_SHELL
  use mefem_output_mesh, only: NODES_OF_TOPO
  use mefem_metis, only: metis_partition_elements
  use mefem_decomposition, only: decomposition_t, build_decomposition
  implicit none
  private

  public :: partition_model, element_csr

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
  subroutine partition_model(model, decomp, element_rank)
    type(model_t), intent(in) :: model               !< resolved model
    type(decomposition_t), intent(out) :: decomp     !< this rank's share
    integer, allocatable, intent(out), optional :: element_rank(:) !< rank of every element
    integer, allocatable :: elem_start(:), elem_nodes(:), elem_part(:)
    type(status_t) :: status
    integer :: ncommon
    call element_csr(model, elem_start, elem_nodes)
    allocate(elem_part(model%elements%n))
    elem_part = 0
    ! neighbours share an edge in 2D or when shells are present, a face otherwise
    ncommon = 3
    if (model%dimension == 2 .or. any(model%elements%keyword(1:model%elements%n) == ELEM_SHELL)) &
      ncommon = 2
    if (comm_size() > 1) then
      if (comm_is_root()) then
        call metis_partition_elements(model%elements%n, model%nodes%n, elem_start, elem_nodes, &
                                      ncommon, comm_size(), elem_part=elem_part, status=status)
      end if
      call comm_bcast(status%ok)
      if (.not. status%ok) then
        if (comm_is_root()) call fatal('partitioning failed: '//status%message)
        call fatal('partitioning failed')
      end if
      call comm_bcast(elem_part)
    end if
    call build_decomposition(comm_rank(), comm_size(), model%elements%n, model%nodes%n, &
                             elem_start, elem_nodes, elem_part, decomp)
    if (present(element_rank)) call move_alloc(elem_part, element_rank)
  end subroutine partition_model

end module mefem_model_partition
