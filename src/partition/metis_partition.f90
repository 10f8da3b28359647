!> Element partitioning with METIS: the only module of mefem that calls METIS.
!>
!> METIS 5.1 is called through its C API (ISO_C_BINDING). In Debian's build idx_t is a
!> 32-bit C int and real_t a 32-bit float, and the options array holds METIS_NOPTIONS = 40
!> entries. The mesh is handed to METIS_PartMeshDual, which builds the dual graph (elements
!> are neighbours when they share at least `ncommon` nodes) and partitions it k-way with a
!> fixed random seed, so that the same mesh always gives the same partition. A sparse
!> matrix's graph is handed to METIS_NodeND for a fill-reducing nested-dissection ordering
!> (the pivot order mefem_mumps gives MUMPS: Debian's MUMPS has no METIS of its own).
module mefem_metis
  use, intrinsic :: iso_c_binding, only: c_int, c_ptr, c_null_ptr, c_loc
  use mefem_errors, only: status_t, warn
  implicit none
  private

  public :: metis_partition_elements, metis_nested_dissection

  integer, parameter :: METIS_NOPTIONS = 40        !< length of METIS's options array
  integer, parameter :: METIS_OK = 1               !< return code: success
  integer, parameter :: METIS_ERROR_INPUT = -2     !< return code: erroneous input or options
  integer, parameter :: METIS_ERROR_MEMORY = -3    !< return code: out of memory
  integer, parameter :: METIS_OPTION_PTYPE = 0     !< 0-based position of the method option
  integer, parameter :: METIS_PTYPE_RB = 0         !< method: recursive bisection
  integer, parameter :: METIS_OPTION_SEED = 8      !< 0-based position of the seed option
  integer, parameter :: METIS_OPTION_NUMBERING = 17 !< 0-based position of the numbering option
  integer, parameter :: PARTITION_SEED = 20130101  !< fixed seed: deterministic partitions

  interface
    !> Fill options with METIS's defaults (all -1).
    function metis_set_default_options(options) bind(C, name='METIS_SetDefaultOptions') &
        result(code)
      import :: c_int
      integer(c_int), intent(inout) :: options(*)  !< (METIS_NOPTIONS) options array
      integer(c_int) :: code
    end function metis_set_default_options

    !> Partition the dual graph of a mesh (METIS_PartMeshDual).
    function metis_part_mesh_dual(nelem, nnode, eptr, eind, vwgt, vsize, ncommon, nparts, &
        tpwgts, options, objval, epart, npart) bind(C, name='METIS_PartMeshDual') result(code)
      import :: c_int, c_ptr
      integer(c_int), intent(in) :: nelem           !< number of elements
      integer(c_int), intent(in) :: nnode           !< number of nodes
      integer(c_int), intent(inout) :: eptr(*)      !< (nelem+1) 0-based start of each element
      integer(c_int), intent(inout) :: eind(*)      !< 0-based node indices of all elements
      type(c_ptr), value :: vwgt                    !< element weights or NULL
      type(c_ptr), value :: vsize                   !< communication sizes (NULL)
      integer(c_int), intent(in) :: ncommon         !< shared nodes that make two neighbours
      integer(c_int), intent(in) :: nparts          !< number of parts
      type(c_ptr), value :: tpwgts                  !< target part weights (NULL: equal)
      integer(c_int), intent(inout) :: options(*)   !< (METIS_NOPTIONS) options
      integer(c_int), intent(out) :: objval         !< edge cut of the result
      integer(c_int), intent(out) :: epart(*)       !< (nelem) part of each element
      integer(c_int), intent(out) :: npart(*)       !< (nnode) part of each node
      integer(c_int) :: code
    end function metis_part_mesh_dual

    !> Fill-reducing ordering of a graph by nested dissection (METIS_NodeND).
    function metis_node_nd(nvtxs, xadj, adjncy, vwgt, options, perm, iperm) &
        bind(C, name='METIS_NodeND') result(code)
      import :: c_int, c_ptr
      integer(c_int), intent(in) :: nvtxs           !< number of vertices
      integer(c_int), intent(inout) :: xadj(*)      !< (nvtxs+1) start of each adjacency list
      integer(c_int), intent(inout) :: adjncy(*)    !< adjacency lists (no self loops)
      type(c_ptr), value :: vwgt                    !< vertex weights (NULL)
      integer(c_int), intent(inout) :: options(*)   !< (METIS_NOPTIONS) options
      integer(c_int), intent(out) :: perm(*)        !< (nvtxs) vertex at each position
      integer(c_int), intent(out) :: iperm(*)       !< (nvtxs) position of each vertex
      integer(c_int) :: code
    end function metis_node_nd
  end interface

contains

  !> Partition the elements of a mesh into nparts parts with METIS (0-based part numbers).
  !> Elements sharing at least ncommon nodes are neighbours in the dual graph: use 2 for 2D
  !> triangle/quadrilateral meshes, 3 for tetrahedra (and mixed 3D meshes), 4 for hexahedra
  !> only. nparts == 1 gives all zeros without calling METIS. Bad input or a METIS failure
  !> gives status%ok = .false. with a message, and elem_part = 0. With bisection = .true.,
  !> METIS bisects recursively instead: the first bisection splits the parts into
  !> 0..nparts/2-1 and nparts/2..nparts-1, and so on down the tree, so that contiguous ranges
  !> of parts are compact pieces of the mesh (mefem_model_partition's chunks).
  subroutine metis_partition_elements(nelem, nnode, elem_start, elem_nodes, ncommon, nparts, &
                                      elem_weight, elem_part, status, bisection)
    integer, intent(in) :: nelem                  !< number of elements
    integer, intent(in) :: nnode                  !< number of nodes
    integer, intent(in) :: elem_start(:)          !< (nelem+1) e has elem_start(e):elem_start(e+1)-1
    integer, intent(in) :: elem_nodes(:)          !< 1-based node indices of all elements
    integer, intent(in) :: ncommon                !< nodes two elements share to be neighbours
    integer, intent(in) :: nparts                 !< number of parts (ranks)
    integer, intent(in), optional :: elem_weight(:) !< (nelem) element costs (>= 0), default 1
    integer, intent(out) :: elem_part(:)          !< (nelem) part of each element, 0..nparts-1
    type(status_t), intent(out) :: status         !< failure and its reason
    logical, intent(in), optional :: bisection    !< recursive bisection (default: k-way)
    integer(c_int), allocatable :: eptr(:), eind(:), epart(:), npart(:)
    integer(c_int), allocatable, target :: weights(:)
    integer(c_int) :: options(METIS_NOPTIONS), objval, code
    integer(c_int) :: nelem_c, nnode_c, ncommon_c, nparts_c
    type(c_ptr) :: weight_ptr
    integer, allocatable :: part_count(:)
    integer :: nconn
    character(len=200) :: text
    character(len=300) :: line

    if (size(elem_part) > 0) elem_part = 0
    call check_input(nelem, nnode, elem_start, elem_nodes, ncommon, nparts, elem_weight, &
                     size(elem_part), status)
    if (.not. status%ok) return
    if (nparts == 1) return

    ! METIS gets 0-based copies (it may rewrite the index arrays during the call).
    nconn = elem_start(nelem + 1) - 1
    allocate(eptr(nelem + 1), eind(nconn), epart(nelem), npart(nnode))
    eptr = int(elem_start(1:nelem + 1) - 1, c_int)
    eind = int(elem_nodes(1:nconn) - 1, c_int)
    weight_ptr = c_null_ptr
    if (present(elem_weight)) then
      allocate(weights(nelem))
      weights = int(elem_weight(1:nelem), c_int)
      weight_ptr = c_loc(weights)
    end if

    code = metis_set_default_options(options)
    options(METIS_OPTION_SEED + 1) = int(PARTITION_SEED, c_int)
    options(METIS_OPTION_NUMBERING + 1) = 0_c_int
    if (present(bisection)) then
      if (bisection) options(METIS_OPTION_PTYPE + 1) = int(METIS_PTYPE_RB, c_int)
    end if
    nelem_c = int(nelem, c_int)
    nnode_c = int(nnode, c_int)
    ncommon_c = int(ncommon, c_int)
    nparts_c = int(nparts, c_int)
    code = metis_part_mesh_dual(nelem_c, nnode_c, eptr, eind, weight_ptr, c_null_ptr, &
                                ncommon_c, nparts_c, c_null_ptr, options, objval, epart, npart)
    if (code /= METIS_OK) then
      status%ok = .false.
      text = error_text(code)
      write(line, '(a,i0,a,i0,a)') 'metis_partition_elements: '//trim(text)// &
          ' partitioning ', nelem, ' elements into ', nparts, ' parts'
      status%message = trim(line)
      return
    end if
    elem_part(1:nelem) = int(epart)

    ! METIS 5.1 may leave a part empty on small or badly connected meshes: say so.
    allocate(part_count(0:nparts - 1))
    part_count = 0
    if (minval(elem_part(1:nelem)) >= 0 .and. maxval(elem_part(1:nelem)) < nparts) then
      call count_parts(elem_part(1:nelem), part_count)
      if (any(part_count == 0) .and. .not. present(bisection)) then    ! (chunks may be empty)
        write(text, '(a,i0,a,i0,a)') 'METIS left ', count(part_count == 0), ' of ', nparts, &
            ' parts empty; those ranks get no elements'
        call warn(trim(text))
      end if
    else
      status%ok = .false.
      status%message = 'metis_partition_elements: METIS returned part numbers out of range'
    end if
  end subroutine metis_partition_elements

  !> Count the elements of each part.
  subroutine count_parts(elem_part, part_count)
    integer, intent(in) :: elem_part(:)           !< part of each element
    integer, intent(inout) :: part_count(0:)      !< elements per part (incremented)
    integer :: e
    do e = 1, size(elem_part)
      part_count(elem_part(e)) = part_count(elem_part(e)) + 1
    end do
  end subroutine count_parts

  !> Check the mesh and the request before METIS sees them.
  subroutine check_input(nelem, nnode, elem_start, elem_nodes, ncommon, nparts, elem_weight, &
                         part_size, status)
    integer, intent(in) :: nelem                  !< number of elements
    integer, intent(in) :: nnode                  !< number of nodes
    integer, intent(in) :: elem_start(:)          !< (nelem+1) element starts
    integer, intent(in) :: elem_nodes(:)          !< 1-based node indices
    integer, intent(in) :: ncommon                !< shared nodes that make neighbours
    integer, intent(in) :: nparts                 !< number of parts
    integer, intent(in), optional :: elem_weight(:) !< element weights
    integer, intent(in) :: part_size              !< size of the output array
    type(status_t), intent(inout) :: status       !< set on failure
    character(len=200) :: text
    integer :: e, nconn

    text = ''
    if (nelem < 1) then
      write(text, '(a,i0)') 'need at least one element, got nelem = ', nelem
    else if (nnode < 1) then
      write(text, '(a,i0)') 'need at least one node, got nnode = ', nnode
    else if (nparts < 1) then
      write(text, '(a,i0)') 'need at least one part, got nparts = ', nparts
    else if (nparts > nelem) then
      write(text, '(a,i0,a,i0,a)') 'cannot split ', nelem, ' elements into ', nparts, ' parts'
    else if (ncommon < 1) then
      write(text, '(a,i0)') 'ncommon must be >= 1, got ', ncommon
    else if (size(elem_start) < nelem + 1) then
      write(text, '(a,i0,a,i0)') 'elem_start has ', size(elem_start), ' entries, need ', nelem + 1
    else if (part_size < nelem) then
      write(text, '(a,i0,a,i0)') 'elem_part has ', part_size, ' entries, need ', nelem
    else if (elem_start(1) /= 1) then
      write(text, '(a,i0)') 'elem_start(1) must be 1, got ', elem_start(1)
    end if
    if (len_trim(text) == 0) then
      do e = 1, nelem
        if (elem_start(e + 1) <= elem_start(e)) then
          write(text, '(a,i0,a)') 'element ', e, ' has no nodes (elem_start not increasing)'
          exit
        end if
      end do
    end if
    if (len_trim(text) == 0) then
      nconn = elem_start(nelem + 1) - 1
      if (nconn > size(elem_nodes)) then
        write(text, '(a,i0,a,i0)') 'elem_nodes has ', size(elem_nodes), ' entries, need ', nconn
      else if (any(elem_nodes(1:nconn) < 1) .or. any(elem_nodes(1:nconn) > nnode)) then
        write(text, '(a,i0)') 'a node index is outside 1..', nnode
      end if
    end if
    if (len_trim(text) == 0 .and. present(elem_weight)) then
      if (size(elem_weight) < nelem) then
        write(text, '(a,i0,a,i0)') 'elem_weight has ', size(elem_weight), ' entries, need ', nelem
      else if (any(elem_weight(1:nelem) < 0)) then
        text = 'element weights must be >= 0'
      else if (all(elem_weight(1:nelem) == 0)) then
        text = 'element weights are all zero'
      end if
    end if
    if (len_trim(text) > 0) then
      status%ok = .false.
      status%message = 'metis_partition_elements: '//trim(text)
    end if
  end subroutine check_input

  !> Fill-reducing pivot order of a symmetric sparsity graph by nested dissection
  !> (METIS_NodeND, fixed seed): position(i) is the elimination position of vertex i
  !> (1-based). The graph is given 1-based in CSR form, both directions of every edge, no
  !> self loops: vertex i's neighbours are columns(row_start(i):row_start(i+1)-1).
  subroutine metis_nested_dissection(n, row_start, columns, position, status)
    integer, intent(in) :: n                      !< number of vertices
    integer, intent(in) :: row_start(:)           !< (n+1) start of each vertex's neighbours
    integer, intent(in) :: columns(:)             !< 1-based neighbours
    integer, intent(out) :: position(:)           !< (n) elimination position of each vertex
    type(status_t), intent(out) :: status         !< failure and its reason
    integer(c_int), allocatable :: xadj(:), adjncy(:), perm(:), iperm(:)
    integer(c_int) :: options(METIS_NOPTIONS), code, n_c
    character(len=300) :: text
    integer :: i
    if (n < 1 .or. size(row_start) < n + 1 .or. size(position) < n) then
      status%ok = .false.
      status%message = 'metis_nested_dissection: inconsistent graph sizes'
      return
    end if
    if (row_start(n + 1) == 1) then     ! no edge: nothing to split, keep the order
      position(1:n) = [(i, i = 1, n)]
      return
    end if
    allocate(xadj(n + 1), adjncy(row_start(n + 1) - 1), perm(n), iperm(n))
    xadj = int(row_start(1:n + 1) - 1, c_int)
    adjncy = int(columns(1:row_start(n + 1) - 1) - 1, c_int)
    code = metis_set_default_options(options)
    options(METIS_OPTION_SEED + 1) = int(PARTITION_SEED, c_int)
    options(METIS_OPTION_NUMBERING + 1) = 0_c_int
    n_c = int(n, c_int)
    code = metis_node_nd(n_c, xadj, adjncy, c_null_ptr, options, perm, iperm)
    if (code /= METIS_OK) then
      status%ok = .false.
      write(text, '(a,i0,a)') 'metis_nested_dissection: '//trim(error_text(code))// &
          ' ordering a graph of ', n, ' vertices'
      status%message = trim(text)
      return
    end if
    do i = 1, n
      position(i) = int(iperm(i)) + 1
    end do
  end subroutine metis_nested_dissection

  !> What a METIS return code other than METIS_OK means.
  function error_text(code) result(text)
    integer(c_int), intent(in) :: code            !< METIS return code
    character(len=80) :: text
    select case (code)
    case (METIS_ERROR_INPUT)
      text = 'METIS rejected the input (METIS_ERROR_INPUT)'
    case (METIS_ERROR_MEMORY)
      text = 'METIS ran out of memory (METIS_ERROR_MEMORY)'
    case default
      write(text, '(a,i0,a)') 'METIS failed (return code ', code, ')'
    end select
  end function error_text

end module mefem_metis
