!> XDMF 3 file beside the HDF5 result (doc/hdf5_layout.md), so that ParaView's Xdmf3 reader and
!> VisIt read the HDF5 data directly, every state a time step. The file only points into the
!> HDF5 file: the reference coordinates, the mixed topology /mesh/xdmf_topology, and per state
!> its time and every point and cell field (ncomp 1: Scalar, 3: Vector, 6: Tensor6 in mefem's
!> order xx yy zz xy yz zx, 9: Tensor, else Matrix). Rank 0 keeps the states' XML and rewrites
!> the file after each state, as the .pvd is, so a run that stops early leaves a readable one.
module mefem_xdmf_output
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_is_root
  use mefem_errors, only: warn
  use mefem_output_mesh, only: output_field_t
  use mefem_strings, only: itoa
  implicit none
  private

  public :: xdmf_open, xdmf_add_state, xdmf_states, xdmf_restore_states

  character(len=*), parameter :: LF = achar(10)   !< line feed

  character(len=:), allocatable :: xdmf_path     !< the .xdmf file
  character(len=:), allocatable :: h5_name       !< the HDF5 file, relative to the .xdmf
  character(len=:), allocatable :: states_xml    !< the <Grid> of every state written so far
  character(len=:), allocatable :: mesh_xml      !< topology and geometry (in every state)
  logical :: writing = .false.                   !< rank 0, and no write has failed
  integer :: nnode = 0, ncell = 0                !< global node and cell counts

contains

  !> Start the XDMF file of a result (rank 0; the others keep nothing).
  subroutine xdmf_open(path, h5file, nnode_global, ncell_global, topology_length)
    character(len=*), intent(in) :: path          !< the .xdmf file
    character(len=*), intent(in) :: h5file        !< the HDF5 file's name beside it
    integer, intent(in) :: nnode_global           !< nodes of the mesh
    integer, intent(in) :: ncell_global           !< cells of the mesh
    integer(i8), intent(in) :: topology_length    !< entries of /mesh/xdmf_topology
    character(len=24) :: topology_text
    writing = comm_is_root()
    if (.not. writing) return
    xdmf_path = path
    h5_name = h5file
    nnode = nnode_global
    ncell = ncell_global
    states_xml = ''
    write(topology_text, '(i0)') topology_length
    topology_text = adjustl(topology_text)
    mesh_xml = &
        '        <Topology TopologyType="Mixed" NumberOfElements="'//itoa(ncell)//'">'//LF// &
        '          '//data_item('/mesh/xdmf_topology', trim(topology_text), 'Int')//LF// &
        '        </Topology>'//LF// &
        '        <Geometry GeometryType="XYZ">'//LF// &
        '          '//data_item('/mesh/coordinates', itoa(nnode)//' 3', 'Float')//LF// &
        '        </Geometry>'//LF
  end subroutine xdmf_open

  !> Add a state (its group /states/SSSSSS, time and fields, as the HDF5 file holds them) and
  !> rewrite the file.
  subroutine xdmf_add_state(step, time, point_fields, cell_fields)
    integer, intent(in) :: step                          !< state number (names the group)
    real(wp), intent(in) :: time                         !< its time
    type(output_field_t), intent(in) :: point_fields(:)  !< its nodal fields
    type(output_field_t), intent(in) :: cell_fields(:)   !< its cell fields
    character(len=32) :: group, time_text
    integer :: f
    if (.not. writing) return
    write(group, '(a,i0.6)') '/states/', step
    write(time_text, '(es24.16e3)') time
    states_xml = states_xml//'      <Grid Name="state '//trim(group(9:))// &
        '" GridType="Uniform">'//LF//'        <Time Value="'//trim(adjustl(time_text))//'"/>'// &
        LF//mesh_xml
    do f = 1, size(point_fields)
      states_xml = states_xml//attribute(trim(group)//'/point/', point_fields(f), 'Node', nnode)
    end do
    do f = 1, size(cell_fields)
      states_xml = states_xml//attribute(trim(group)//'/cell/', cell_fields(f), 'Cell', ncell)
    end do
    states_xml = states_xml//'      </Grid>'//LF
    call rewrite()
  end subroutine xdmf_add_state

  !> The <Grid> XML of the states written so far (rank 0; empty elsewhere), for a restart file.
  function xdmf_states() result(xml)
    character(len=:), allocatable :: xml
    xml = ''
    if (writing) xml = states_xml
  end function xdmf_states

  !> List the states given (xdmf_states of the run a restart file was written by) and
  !> rewrite the file (after xdmf_open).
  subroutine xdmf_restore_states(xml)
    character(len=*), intent(in) :: xml               !< the states' <Grid> XML
    if (.not. writing) return
    states_xml = xml
    call rewrite()
  end subroutine xdmf_restore_states

  !> Write the whole file anew; a failure is warned about once and ends the XDMF output.
  subroutine rewrite()
    integer :: unit, ios
    open(newunit=unit, file=xdmf_path, status='replace', action='write', form='formatted', &
         iostat=ios)
    if (ios == 0) write(unit, '(a)', iostat=ios) '<?xml version="1.0" ?>'//LF// &
        '<Xdmf Version="3.0">'//LF//'  <Domain>'//LF// &
        '    <Grid Name="mefem" GridType="Collection" CollectionType="Temporal">'//LF// &
        states_xml//'    </Grid>'//LF//'  </Domain>'//LF//'</Xdmf>'
    if (ios == 0) close(unit, iostat=ios)
    if (ios /= 0) then
      call warn('results: cannot write '//xdmf_path//' (the XDMF file for ParaView and '// &
                'VisIt); the .pvd and .h5 results are not affected')
      writing = .false.
    end if
  end subroutine rewrite

  !> One <Attribute> with its DataItem: a field of n rows and ncomp components.
  function attribute(prefix, field, center, n) result(xml)
    character(len=*), intent(in) :: prefix            !< "/states/SSSSSS/point/" or ".../cell/"
    type(output_field_t), intent(in) :: field         !< the field
    character(len=*), intent(in) :: center            !< "Node" or "Cell"
    integer, intent(in) :: n                          !< rows (global nodes or cells)
    character(len=:), allocatable :: xml
    character(len=8) :: kind
    select case (field%ncomp)
    case (1)
      kind = 'Scalar'
    case (3)
      kind = 'Vector'
    case (6)
      kind = 'Tensor6'
    case (9)
      kind = 'Tensor'
    case default
      kind = 'Matrix'
    end select
    xml = '        <Attribute Name="'//trim(field%name)//'" AttributeType="'//trim(kind)// &
        '" Center="'//center//'">'//LF//'          '// &
        data_item(prefix//trim(field%name), itoa(n)//' '//itoa(field%ncomp), 'Float')//LF// &
        '        </Attribute>'//LF
  end function attribute

  !> A DataItem pointing to a dataset of the HDF5 file (8-byte numbers).
  function data_item(dataset, dimensions, number_type) result(xml)
    character(len=*), intent(in) :: dataset           !< its path in the HDF5 file
    character(len=*), intent(in) :: dimensions        !< "n" or "n m"
    character(len=*), intent(in) :: number_type       !< "Int" or "Float"
    character(len=:), allocatable :: xml
    xml = '<DataItem Dimensions="'//dimensions//'" NumberType="'//number_type// &
        '" Precision="8" Format="HDF">'//h5_name//':'//dataset//'</DataItem>'
  end function data_item

end module mefem_xdmf_output
