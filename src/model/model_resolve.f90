!> Cross-checks the model after reading: ids to indices, element topology and orientation,
!> parts to sections and materials, supported element formulations, 2D or 3D.
!>
!> Every problem is reported with the file:line of the record that holds the bad reference,
!> all in one pass. References of sets, curves, loads, contacts and outputs are resolved by
!> mefem_resolve_conditions, called from here.
module mefem_model_resolve
  use mefem_kinds, only: wp
  use mefem_vector_math, only: cross
  use mefem_errors, only: input_error, input_error_count, say, warn
  use mefem_strings, only: itoa, rtoa
  use mefem_deck_source, only: location
  use mefem_id_map, only: id_map_t, id_map_build, id_map_find
  use mefem_model, only: model_t, source_t, elements_t, TC_FIXED, ELEM_SOLID, ELEM_SHELL, SECTION_SOLID, &
                         SECTION_SHELL, MAT_RIGID, TOPO_TRI3, TOPO_QUAD4, TOPO_TET4, &
                         TOPO_PENTA6, TOPO_HEX8, ON_NODE, ON_NODE_SET, ON_PART, ON_PART_SET
  use mefem_output_mesh, only: NODES_OF_TOPO
  use mefem_resolve_conditions, only: resolve_conditions, resolve_segment_sets
  implicit none
  private

  public :: model_resolve, element_measure, element_mass, formulation_name, part_hourglass, &
            hexahedral_formulation

  ! element formulations mefem computes (ELFORM of *SECTION_SOLID / *SECTION_SHELL)
  integer, parameter, public :: ELFORM_TET_STANDARD = 10       !< linear tetrahedron
  integer, parameter, public :: ELFORM_MEFEM = 43              !< ME-FEM tet / plane-strain triangle
  integer, parameter, public :: ELFORM_TRI_PLANE_STRAIN = 13   !< linear plane-strain triangle
  integer, parameter, public :: ELFORM_TET_NODAL_PRESSURE = 13 !< linear tetrahedron with the
                                                               !< volume averaged at the nodes

  integer, parameter, public :: ELFORM_HEX_ONE_POINT = 1      !< one-point hexahedron with
                                                               !< hourglass control
  ! the fully integrated hexahedra computed as ELFORM 1 with the physical stiffness hourglass
  ! control (IHQ 6, QM 1), with a warning naming the part
  integer, parameter :: ELFORM_HEX_FULLY_INTEGRATED(3) = [2, -1, -2]

  ! LS-DYNA's solid formulations that mefem does not compute for deformable parts: ELFORM
  ! ranges, what they are, what to do instead (unsupported_solid_text)
  integer, parameter :: N_SOLID_ELFORM_ROWS = 11
  integer, parameter :: SOLID_ELFORM_FIRST(N_SOLID_ELFORM_ROWS) = &
      [0, 3, 9, 4, 15, 16, 18, 19, 23, 41, 101]
  integer, parameter :: SOLID_ELFORM_LAST(N_SOLID_ELFORM_ROWS) = &
      [0, 3, 9, 4, 15, 17, 18, 22, 23, 47, 105]
  character(len=*), parameter :: USE_ONE_POINT = 'use 1 (one-point hexahedron with '// &
      'hourglass control)'
  character(len=48), parameter :: SOLID_ELFORM_NAME(N_SOLID_ELFORM_ROWS) = [character(len=48) :: &
      'a co-rotational hexahedron', 'a hexahedron with nodal rotations', &
      'a co-rotational hexahedron', 'a quadratic tetrahedron', 'a pentahedron', &
      'a 10-node tetrahedron', 'an enhanced-strain hexahedron', 'a cohesive element', &
      'a 20-node hexahedron', 'a meshfree solid (EFG, SPG)', 'a user element']
  character(len=112), parameter :: SOLID_ELFORM_ADVICE(N_SOLID_ELFORM_ROWS) = &
      [character(len=112) :: USE_ONE_POINT, USE_ONE_POINT, USE_ONE_POINT, &
      'give the 4 corner nodes of each tetrahedron and use 43 or 13', &
      'give the pentahedra as LS-DYNA''s degenerate hexahedra and use 1', &
      'give the 4 corner nodes of each tetrahedron and use 43 or 13', USE_ONE_POINT, &
      'cohesive elements are not computed', USE_ONE_POINT, &
      'ME-FEM (43) is the meshfree-enriched tetrahedron mefem computes', &
      'user elements are not computed']

  !> Outward faces of a hexahedron (LS-DYNA order: N1-N4 bottom, N5-N8 top); degenerate
  !> elements (tets, pentas) are measured through their collapsed 8-node form.
  integer, parameter :: HEX_FACES(4, 6) = reshape([1, 4, 3, 2,  5, 6, 7, 8,  1, 2, 6, 5, &
                                                   2, 3, 7, 6,  3, 4, 8, 7,  4, 1, 5, 8], [4, 6])

contains

  !> Resolve and check the whole model; errors are counted by mefem_errors.
  subroutine model_resolve(model)
    type(model_t), intent(inout) :: model   !< the model read from the deck
    type(id_map_t) :: node_map, part_map, section_map, material_map, curve_map
    integer :: k
    call id_map_build(model%nodes%id, model%nodes%n, node_map)
    call report_duplicates(node_map, model%nodes%src, '*NODE', 'node')
    if (.not. allocated(model%parts)) allocate(model%parts(0))
    if (.not. allocated(model%sections)) allocate(model%sections(0))
    call id_map_build(model%parts(1:model%n_parts)%id, model%n_parts, part_map)
    call report_duplicates(part_map, model%parts(1:model%n_parts)%src, '*PART', 'part')
    call id_map_build(model%sections(1:model%n_sections)%id, model%n_sections, section_map)
    call report_duplicates(section_map, model%sections(1:model%n_sections)%src, '*SECTION', &
                           'section')
    call resolve_conditions(model, node_map, part_map, material_map, curve_map)
    do k = 1, model%n_parts
      call resolve_part(model, k, section_map, material_map)
      associate (part => model%parts(k))
        if (part%has_inertia .and. part%inertia_node_id > 0) then
          part%inertia_node = id_map_find(node_map, part%inertia_node_id)
          if (part%inertia_node == 0) call input_error(location(part%inertia_src%file, &
              part%inertia_src%line)//': *PART_INERTIA', 'part '//itoa(part%id)//': NODEID: '// &
              'node '//itoa(part%inertia_node_id)//' is not defined')
        end if
      end associate
    end do
    call resolve_elements(model, node_map, part_map)
    call resolve_segment_sets(model, node_map, part_map)
    call apply_global_constraints(model)
    allocate(model%nodes%added_mass(model%nodes%n))
    model%nodes%added_mass = 0.0_wp
    if (input_error_count() == 0) call distribute_added_masses(model)
    ! an empty model is worth a message only when nothing else was wrong (an unreadable deck
    ! has no nodes as a consequence)
    if (input_error_count() == 0) then
      if (model%nodes%n == 0) call input_error('', 'the deck defines no nodes (*NODE)')
      if (model%elements%n == 0) call input_error('', 'the deck defines no elements '// &
          '(*ELEMENT_SOLID or *ELEMENT_SHELL)')
    end if
    ! what only the resolution reads, freed (every rank holds the model: 48 bytes per element
    ! and 8 per node): the elements' user node ids (conn holds the node indices) and the deck
    ! lines of the elements and nodes (later messages name them by id)
    if (allocated(model%elements%node_ids)) deallocate(model%elements%node_ids)
    if (allocated(model%elements%src)) deallocate(model%elements%src)
    if (allocated(model%nodes%src)) deallocate(model%nodes%src)
  end subroutine model_resolve

  !> Report every id that occurs more than once (at each later occurrence).
  subroutine report_duplicates(map, src, keyword, what)
    type(id_map_t), intent(in) :: map          !< sorted ids
    type(source_t), intent(in) :: src(:)       !< where each record was read
    character(len=*), intent(in) :: keyword    !< keyword for the message
    character(len=*), intent(in) :: what       !< 'node', 'part', ...
    integer :: k
    do k = 2, map%n
      if (map%ids(k) == map%ids(k-1)) then
        call input_error(location(src(map%index(k))%file, src(map%index(k))%line)//': '// &
            keyword, what//' id '//itoa(map%ids(k))//' is defined twice (first at '// &
            location(src(map%index(k-1))%file, src(map%index(k-1))%line)//')')
      end if
    end do
  end subroutine report_duplicates

  !> Report every element id given twice to elements of one keyword (solids and shells have
  !> separate id spaces, as in LS-DYNA: a solid and a shell may share an id).
  subroutine report_duplicate_elements(map, el)
    type(id_map_t), intent(in) :: map          !< sorted element ids
    type(elements_t), intent(in) :: el         !< the elements
    integer :: k, j, a, b
    do k = 2, map%n
      if (map%ids(k) /= map%ids(k-1)) cycle
      a = map%index(k)
      do j = k - 1, 1, -1                       ! the earlier elements of the same id
        if (map%ids(j) /= map%ids(k)) exit
        b = map%index(j)
        if (el%keyword(b) /= el%keyword(a)) cycle
        call input_error(location(el%src(a)%file, el%src(a)%line)//': '// &
            trim(merge('*ELEMENT_SOLID', '*ELEMENT_SHELL', el%keyword(a) == ELEM_SOLID)), &
            'element id '//itoa(map%ids(k))//' is defined twice (first at '// &
            location(el%src(b)%file, el%src(b)%line)//')')
        exit
      end do
    end do
  end subroutine report_duplicate_elements

  !> Part k: its section and material exist and the formulation is one mefem computes.
  subroutine resolve_part(model, k, section_map, material_map)
    type(model_t), intent(inout) :: model          !< the model
    integer, intent(in) :: k                       !< part index
    type(id_map_t), intent(in) :: section_map, material_map  !< id maps
    character(len=:), allocatable :: where
    integer :: h
    associate (part => model%parts(k))
      where = location(part%src%file, part%src%line)//': *PART'
      part%section = id_map_find(section_map, part%section_id)
      part%material = id_map_find(material_map, part%material_id)
      ! (a section or material rejected where it is defined has been reported there)
      if (part%section == 0 .and. .not. listed(model%rejected_section_ids, part%section_id)) &
        call input_error(where, 'part '//itoa(part%id)//': section '// &
                         itoa(part%section_id)//' (SECID) is not defined')
      if (part%material == 0 .and. .not. listed(model%rejected_material_ids, &
                                                part%material_id)) &
        call input_error(where, 'part '//itoa(part%id)//': material '// &
                         itoa(part%material_id)//' (MID) is not defined')
      part%hourglass = 0
      if (part%hourglass_id /= 0) then
        do h = 1, model%n_hourglasses
          if (model%hourglasses(h)%id == part%hourglass_id) part%hourglass = h
        end do
        if (part%hourglass == 0) call input_error(where, 'part '//itoa(part%id)// &
            ': hourglass control '//itoa(part%hourglass_id)//' (HGID) is not defined '// &
            '(*HOURGLASS)')
      end if
      if (part%has_inertia .and. part%material > 0) then
        if (model%materials(part%material)%kind /= MAT_RIGID) call input_error( &
            location(part%inertia_src%file, part%inertia_src%line)//': *PART_INERTIA', &
            'part '//itoa(part%id)//': the mass properties of *PART_INERTIA are those of a '// &
            'rigid body; the part''s material is not *MAT_RIGID')
      end if
    end associate
  end subroutine resolve_part

  !> Elements: nodes and parts exist, topology, formulation and positive volume or area.
  subroutine resolve_elements(model, node_map, part_map)
    type(model_t), intent(inout) :: model          !< the model
    type(id_map_t), intent(in) :: node_map, part_map  !< id maps
    type(id_map_t) :: element_map
    integer :: e, i, n_solid_deformable, n_shell_deformable, n_before
    logical :: part_reported(model%n_parts)
    logical :: ok
    associate (el => model%elements)
      allocate(el%part(el%n), el%topology(el%n), el%conn(8, el%n))
      call id_map_build(el%id, el%n, element_map)
      call report_duplicate_elements(element_map, el)
      n_solid_deformable = 0
      n_shell_deformable = 0
      part_reported = .false.
      do e = 1, el%n
        el%conn(:, e) = 0
        ok = .true.
        do i = 1, 8
          if (el%node_ids(i, e) == 0) cycle
          el%conn(i, e) = id_map_find(node_map, el%node_ids(i, e))
          if (el%conn(i, e) == 0 .and. .not. any(el%node_ids(1:i-1, e) == el%node_ids(i, e))) &
            then
            call input_error(element_where(model, e), 'element '//itoa(el%id(e))//': node '// &
                itoa(el%node_ids(i, e))//' (N'//itoa(i)//') is not defined')
            ok = .false.
          end if
        end do
        el%part(e) = id_map_find(part_map, el%part_id(e))
        if (el%part(e) == 0) then
          call input_error(element_where(model, e), 'element '//itoa(el%id(e))//': part '// &
              itoa(el%part_id(e))//' (PID) is not defined')
          ok = .false.
        end if
        call classify(el%keyword(e), el%conn(:, e), el%topology(e))
        if (el%topology(e) == 0) then
          call input_error(element_where(model, e), 'element '//itoa(el%id(e))//': nodes '// &
              node_list(el%node_ids(:, e))//' form no tetrahedron, pentahedron or hexahedron'// &
              ' (repeated nodes in unexpected places)')
          ok = .false.
        end if
        if (.not. ok) cycle
        n_before = n_shell_deformable
        call check_formulation(model, e, n_solid_deformable, n_shell_deformable, part_reported)
        call check_measure(model, e, n_shell_deformable > n_before)
      end do
      if (n_solid_deformable > 0 .and. n_shell_deformable > 0) call input_error('', &
          'the model mixes deformable solids (3D) and plane-strain triangles (2D); '// &
          'one analysis is either 2D or 3D')
      model%dimension = 3
      if (n_shell_deformable > 0) model%dimension = 2
    end associate
  end subroutine resolve_elements

  !> Topology from the node pattern, with the corner nodes rearranged in output (VTK) order.
  subroutine classify(keyword, conn, topology)
    integer, intent(in) :: keyword         !< ELEM_SOLID or ELEM_SHELL
    integer, intent(inout) :: conn(8)      !< node indices; rearranged
    integer, intent(out) :: topology       !< TOPO_* or 0 when not recognised
    integer :: c(8)
    c = conn
    topology = 0
    if (keyword == ELEM_SHELL) then
      if (c(4) == c(3) .or. c(4) == 0) then
        if (distinct(c(1:3))) topology = TOPO_TRI3
        conn(4:8) = 0
      else if (distinct(c(1:4))) then
        topology = TOPO_QUAD4
        conn(5:8) = 0
      end if
      return
    end if
    if (all(c(5:8) == c(4)) .and. distinct(c(1:4))) then
      topology = TOPO_TET4
      conn(5:8) = 0
    else if (c(5) == c(6) .and. c(7) == c(8) .and. distinct([c(1:5), c(7)])) then
      ! LS-DYNA pentahedron N1 N2 N3 N4 N5 N5 N6 N6: wedge triangles (N1,N2,N5), (N4,N3,N6)
      topology = TOPO_PENTA6
      conn(1:6) = [c(1), c(2), c(5), c(4), c(3), c(7)]
      conn(7:8) = 0
    else if (distinct(c)) then
      topology = TOPO_HEX8
    end if
  end subroutine classify

  !> True when all entries differ.
  pure logical function distinct(v)
    integer, intent(in) :: v(:)   !< node indices
    integer :: i
    distinct = .true.
    do i = 2, size(v)
      if (any(v(1:i-1) == v(i))) distinct = .false.
    end do
  end function distinct

  !> "file:line: *SECTION_SOLID" (or _SHELL) of section s, for messages.
  function section_where(model, s) result(text)
    type(model_t), intent(in) :: model   !< the model
    integer, intent(in) :: s             !< section index
    character(len=:), allocatable :: text
    text = location(model%sections(s)%src%file, model%sections(s)%src%line)//': '// &
           merge('*SECTION_SOLID', '*SECTION_SHELL', model%sections(s)%kind == SECTION_SOLID)
  end function section_where

  !> "file:line: *ELEMENT_SOLID" (or _SHELL) of element e, for messages. Built only when a
  !> message is given: building it for every element costs more than checking the element.
  function element_where(model, e) result(s)
    type(model_t), intent(in) :: model   !< the model
    integer, intent(in) :: e             !< element index
    character(len=:), allocatable :: s
    s = location(model%elements%src(e)%file, model%elements%src(e)%line)//': '// &
        merge('*ELEMENT_SOLID', '*ELEMENT_SHELL', model%elements%keyword(e) == ELEM_SOLID)
  end function element_where

  !> The element's part uses a formulation mefem computes for its topology.
  subroutine check_formulation(model, e, n_solid_deformable, n_shell_deformable, part_reported)
    type(model_t), intent(in) :: model          !< the model
    integer, intent(in) :: e                    !< element index
    integer, intent(inout) :: n_solid_deformable, n_shell_deformable  !< counters
    logical, intent(inout) :: part_reported(:)  !< an unsupported ELFORM was reported per part
    integer :: p, s, m, elform, topo
    logical :: hexahedral
    p = model%elements%part(e)
    s = model%parts(p)%section
    m = model%parts(p)%material
    if (s == 0 .or. m == 0) return
    topo = model%elements%topology(e)
    elform = model%sections(s)%elform
    if (model%elements%keyword(e) == ELEM_SOLID .and. model%sections(s)%kind /= SECTION_SOLID) &
      then
      call input_error(element_where(model, e), &
          'element '//itoa(model%elements%id(e))//': part '// &
          itoa(model%parts(p)%id)//' has a *SECTION_SHELL but the element is a solid')
      return
    end if
    if (model%elements%keyword(e) == ELEM_SHELL .and. model%sections(s)%kind /= SECTION_SHELL) &
      then
      call input_error(element_where(model, e), &
          'element '//itoa(model%elements%id(e))//': part '// &
          itoa(model%parts(p)%id)//' has a *SECTION_SOLID but the element is a shell')
      return
    end if
    if (model%materials(m)%kind == MAT_RIGID) return      ! rigid parts: any topology
    if (model%elements%keyword(e) == ELEM_SOLID) then
      n_solid_deformable = n_solid_deformable + 1
      hexahedral = hexahedral_formulation(elform)
      if (.not. (hexahedral .or. elform == ELFORM_TET_STANDARD .or. elform == ELFORM_MEFEM &
                 .or. elform == ELFORM_TET_NODAL_PRESSURE)) then
        ! once per part, where it is to be mended: the section, not each element
        if (.not. part_reported(p)) call input_error(section_where(model, s), &
            'section '//itoa(model%sections(s)%id)//': solid ELFORM '//itoa(elform)// &
            unsupported_solid_text(elform)//'; mefem computes 1 one-point hexahedron, 43 '// &
            'ME-FEM tetrahedron, 13 nodal-pressure tetrahedron, 10 standard linear '// &
            'tetrahedron; part '//itoa(model%parts(p)%id)//', first element '// &
            itoa(model%elements%id(e))//' at '//element_where(model, e))
        part_reported(p) = .true.
      else if (.not. hexahedral .and. topo /= TOPO_TET4) then
        call input_error(element_where(model, e), &
            'element '//itoa(model%elements%id(e))//': part '// &
            itoa(model%parts(p)%id)//': ELFORM '//itoa(elform)// &
            ' needs tetrahedra; this element is not one')
      else if (elform /= ELFORM_HEX_ONE_POINT .and. hexahedral .and. .not. part_reported(p)) &
        then
        call warn(section_where(model, s)//': section '//itoa(model%sections(s)%id)// &
            ': solid ELFORM '//itoa(elform)//' (fully integrated hexahedron) is computed as '// &
            'ELFORM 1, the one-point hexahedron, with the physical stiffness hourglass '// &
            'control (IHQ 6, QM 1: the elastic bending stiffness without shear locking); '// &
            'part '//itoa(model%parts(p)%id))
        part_reported(p) = .true.
      end if
    else
      n_shell_deformable = n_shell_deformable + 1
      if (elform /= ELFORM_TRI_PLANE_STRAIN .and. elform /= ELFORM_MEFEM) then
        if (.not. part_reported(p)) call input_error(section_where(model, s), &
            'section '//itoa(model%sections(s)%id)//': shell ELFORM '//itoa(elform)// &
            ' is not supported for deformable parts (43 ME-FEM plane-strain triangle, 13 '// &
            'standard plane-strain triangle; shells of *MAT_RIGID parts may be tool '// &
            'surfaces); part '//itoa(model%parts(p)%id)//', first element '// &
            itoa(model%elements%id(e))//' at '//element_where(model, e))
        part_reported(p) = .true.
      else if (topo /= TOPO_TRI3) then
        call input_error(element_where(model, e), &
            'element '//itoa(model%elements%id(e))//': part '// &
            itoa(model%parts(p)%id)//': plane-strain ELFORM '//itoa(elform)// &
            ' needs triangles; this element is a quadrilateral')
      end if
    end if
  end subroutine check_formulation

  !> What LS-DYNA's solid ELFORM is and what to use instead, for the message of a deformable
  !> part whose formulation mefem does not compute (the table SOLID_ELFORM_*).
  function unsupported_solid_text(elform) result(text)
    integer, intent(in) :: elform            !< the section's ELFORM
    character(len=:), allocatable :: text
    integer :: k
    text = ' is not supported for deformable parts'
    do k = 1, size(SOLID_ELFORM_FIRST)
      if (elform < SOLID_ELFORM_FIRST(k) .or. elform > SOLID_ELFORM_LAST(k)) cycle
      text = ' ('//trim(SOLID_ELFORM_NAME(k))//') is not supported for deformable parts: '// &
             trim(SOLID_ELFORM_ADVICE(k))
      return
    end do
  end function unsupported_solid_text

  !> Volume (solids) or area (shells) must be positive; plane-strain triangles lie in z = 0
  !> and run counter-clockwise about +z.
  subroutine check_measure(model, e, plane_strain)
    type(model_t), intent(in) :: model          !< the model
    integer, intent(in) :: e                    !< element index
    logical, intent(in) :: plane_strain         !< a deformable plane-strain triangle
    real(wp) :: measure, size_scale
    integer :: nn, i
    real(wp) :: xe(3, 8)
    nn = NODES_OF_TOPO(model%elements%topology(e))
    do i = 1, nn      ! a loop: the vector-subscript form allocates a temporary per element
      xe(:, i) = model%nodes%x(:, model%elements%conn(i, e))
    end do
    measure = element_measure(model%elements%topology(e), xe(:, 1:nn))
    size_scale = 0.0_wp
    do i = 1, 3
      size_scale = max(size_scale, maxval(xe(i, 1:nn)) - minval(xe(i, 1:nn)))
    end do
    if (model%elements%keyword(e) == ELEM_SOLID) then
      if (measure <= 1.0e-12_wp*size_scale**3) call input_error(element_where(model, e), &
          'element '//itoa(model%elements%id(e))//' has zero or negative volume ('// &
          rtoa(measure)// &
          '): check its node order (N1-N2-N3 counter-clockwise seen from N4 for a tet)')
    else if (plane_strain) then
      if (any(xe(3, 1:nn) /= 0.0_wp)) then
        call input_error(element_where(model, e), &
            'element '//itoa(model%elements%id(e))//': plane-strain '// &
            'triangles must lie in the x-y plane (z = 0)')
      else if (measure <= 1.0e-12_wp*size_scale**2) then
        call input_error(element_where(model, e), &
            'element '//itoa(model%elements%id(e))//' has zero or '// &
            'negative area ('//rtoa(measure)//'): N1-N2-N3 must run counter-clockwise about +z')
      end if
    else if (abs(measure) <= 1.0e-12_wp*size_scale**2) then
      call input_error(element_where(model, e), 'element '//itoa(model%elements%id(e))// &
          ' has zero area (its nodes are collinear or repeated)')
    end if
  end subroutine check_measure

  !> Signed volume of a solid (through its collapsed-hexahedron faces) or, for a shell, the
  !> area (signed about +z for triangles and quads in the x-y plane, else unsigned).
  pure real(wp) function element_measure(topology, xe)
    integer, intent(in) :: topology     !< TOPO_* code
    real(wp), intent(in) :: xe(:,:)     !< (3, corner nodes) coordinates in output order
    real(wp) :: xh(3, 8), a(3), b(3), c(3), centre(3), area(3)
    integer :: f, i, map(8)
    select case (topology)
    case (TOPO_TRI3, TOPO_QUAD4)
      area = 0.0_wp
      do i = 1, size(xe, 2)
        area = area + cross(xe(:, i), xe(:, modulo(i, size(xe, 2)) + 1))
      end do
      area = 0.5_wp*area
      if (all(xe(3, :) == xe(3, 1))) then
        element_measure = area(3)
      else
        element_measure = norm2(area)
      end if
      return
    case (TOPO_TET4)
      element_measure = dot_product(cross(xe(:, 2) - xe(:, 1), xe(:, 3) - xe(:, 1)), &
                                    xe(:, 4) - xe(:, 1))/6.0_wp
      return
    case (TOPO_PENTA6)
      map = [1, 2, 5, 4, 3, 3, 6, 6]
    case default
      map = [1, 2, 3, 4, 5, 6, 7, 8]
    end select
    xh = xe(:, map)
    element_measure = 0.0_wp
    do f = 1, 6
      centre = 0.25_wp*sum(xh(:, HEX_FACES(:, f)), dim=2)
      do i = 1, 4
        a = xh(:, HEX_FACES(i, f))
        b = xh(:, HEX_FACES(modulo(i, 4) + 1, f))
        c = cross(a - centre, b - centre)
        element_measure = element_measure + dot_product(centre, c)/6.0_wp
      end do
    end do
  end function element_measure


  !> *CONSTRAINED_GLOBAL: each node on a constraint's plane (within TOL; TOL = 0: 1e-6 of the
  !> model's largest extent) gets the constraint's TC joined to its own *NODE TC code. A
  !> constraint that holds no node gets a warning.
  subroutine apply_global_constraints(model)
    type(model_t), intent(inout) :: model     !< the model (nodes read)
    real(wp) :: tolerance, extent
    logical :: held(3)
    integer :: k, n, code, count_on
    if (model%n_global_constraints == 0 .or. model%nodes%n == 0) return
    extent = maxval(maxval(model%nodes%x(:, 1:model%nodes%n), dim=2) - &
                    minval(model%nodes%x(:, 1:model%nodes%n), dim=2))
    do k = 1, model%n_global_constraints
      associate (gc => model%global_constraints(k))
        tolerance = gc%tolerance
        if (tolerance == 0.0_wp) tolerance = 1.0e-6_wp*extent
        count_on = 0
        do n = 1, model%nodes%n
          if (abs(model%nodes%x(gc%direction, n) - gc%point(gc%direction)) > tolerance) cycle
          count_on = count_on + 1
          held = TC_FIXED(:, model%nodes%tc(n)) .or. TC_FIXED(:, gc%tc)
          do code = 0, 7
            if (all(TC_FIXED(:, code) .eqv. held)) model%nodes%tc(n) = code
          end do
        end do
        if (count_on == 0) call warn(location(gc%src%file, gc%src%line)// &
            ': *CONSTRAINED_GLOBAL: no node lies on the plane '// &
            'xyz'(gc%direction:gc%direction)//' = '// &
            rtoa(gc%point(gc%direction))//' (within '//rtoa(tolerance)//'): it holds nothing')
      end associate
    end do
  end subroutine apply_global_constraints

  !> Mass of element e: density times volume (shells: area times the section's thickness T1;
  !> plane strain: per unit thickness), in the reference configuration.
  real(wp) function element_mass(model, e)
    type(model_t), intent(in) :: model     !< resolved model
    integer, intent(in) :: e               !< element index
    real(wp) :: xe(3, 8), thickness
    integer :: i, nn, p
    element_mass = 0.0_wp
    p = model%elements%part(e)
    if (p <= 0) return
    if (model%parts(p)%material <= 0) return
    nn = NODES_OF_TOPO(model%elements%topology(e))
    do i = 1, nn
      xe(:, i) = model%nodes%x(:, model%elements%conn(i, e))
    end do
    thickness = 1.0_wp
    if (model%dimension == 3 .and. model%parts(p)%section > 0) then
      if (model%sections(model%parts(p)%section)%kind == SECTION_SHELL) &
          thickness = model%sections(model%parts(p)%section)%thickness(1)
    end if
    element_mass = model%materials(model%parts(p)%material)%density* &
                   abs(element_measure(model%elements%topology(e), xe(:, 1:nn)))*thickness
  end function element_mass

  !> model%nodes%added_mass from *ELEMENT_MASS (on a node; a node set's nodes share MASS
  !> equally) and *ELEMENT_MASS_PART (ADDMASS, or FINMASS less the parts' mass, spread over
  !> the nodes of the part or part set in proportion to their share of its element mass: an
  !> element's mass split equally among its corners, as the lumped mass of a linear element).
  subroutine distribute_added_masses(model)
    type(model_t), intent(inout) :: model     !< resolved model
    real(wp), allocatable :: share(:)
    logical, allocatable :: in_parts(:)
    real(wp) :: total, added, me
    integer :: k, e, i, nn
    character(len=:), allocatable :: where
    do k = 1, model%n_added_masses
      associate (am => model%added_masses(k))
        if (am%target <= 0) cycle
        select case (am%target_kind)
        case (ON_NODE)
          model%nodes%added_mass(am%target) = model%nodes%added_mass(am%target) + am%mass
        case (ON_NODE_SET)
          associate (members => model%sets(am%target)%members)
            if (size(members) == 0) cycle
            do i = 1, size(members)
              model%nodes%added_mass(members(i)) = model%nodes%added_mass(members(i)) + &
                                                   am%mass/real(size(members), wp)
            end do
          end associate
        case (ON_PART, ON_PART_SET)
          where = location(am%src%file, am%src%line)//': *ELEMENT_MASS_PART'
          allocate(in_parts(model%n_parts), share(model%nodes%n))
          in_parts = .false.
          if (am%target_kind == ON_PART) then
            in_parts(am%target) = .true.
          else
            in_parts(model%sets(am%target)%members) = .true.
          end if
          share = 0.0_wp
          total = 0.0_wp
          do e = 1, model%elements%n
            if (.not. in_parts(model%elements%part(e))) cycle
            me = element_mass(model, e)
            nn = NODES_OF_TOPO(model%elements%topology(e))
            do i = 1, nn
              share(model%elements%conn(i, e)) = share(model%elements%conn(i, e)) + &
                                                 me/real(nn, wp)
            end do
            total = total + me
          end do
          added = am%mass
          if (am%final_mass > 0.0_wp) added = am%final_mass - total
          if (.not. total > 0.0_wp) then
            call input_error(where, trim(merge('part    ', 'part set', am%target_kind == &
                ON_PART))//' '//itoa(am%target_id)//' has no mass (no elements, or density '// &
                '0) to spread the added mass over')
          else if (added < 0.0_wp) then
            call input_error(where, trim(merge('part    ', 'part set', am%target_kind == &
                ON_PART))//' '//itoa(am%target_id)//': FINMASS = '//rtoa(am%final_mass)// &
                ' is below the mass of its elements, '//rtoa(total))
          else
            model%nodes%added_mass = model%nodes%added_mass + added*share/total
          end if
          deallocate(in_parts, share)
        end select
      end associate
    end do
  end subroutine distribute_added_masses

  !> "a b c d" list of the nonzero node ids.
  function node_list(ids) result(s)
    integer, intent(in) :: ids(:)   !< node ids
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, size(ids)
      if (ids(i) /= 0) s = s//' '//itoa(ids(i))
    end do
    s = trim(adjustl(s))
  end function node_list

  !> Name of the formulation of a part, for the run log.
  function formulation_name(model, p) result(s)
    type(model_t), intent(in) :: model   !< the model
    integer, intent(in) :: p             !< part index
    character(len=:), allocatable :: s
    integer :: sec, mat, ihq
    real(wp) :: qm
    sec = model%parts(p)%section
    mat = model%parts(p)%material
    s = 'unknown'
    if (sec == 0 .or. mat == 0) return
    if (model%materials(mat)%kind == MAT_RIGID) then
      s = 'rigid body'
    else if (model%sections(sec)%kind == SECTION_SOLID) then
      select case (model%sections(sec)%elform)
      case (ELFORM_MEFEM)
        s = 'ME-FEM tetrahedron (ELFORM 43)'
      case (ELFORM_TET_STANDARD)
        s = 'standard linear tetrahedron (ELFORM 10)'
      case (ELFORM_TET_NODAL_PRESSURE)
        s = 'nodal-pressure tetrahedron (ELFORM 13)'
      case default
        if (hexahedral_formulation(model%sections(sec)%elform)) then
          call part_hourglass(model, p, ihq, qm)
          s = 'one-point hexahedron (ELFORM 1'
          if (model%sections(sec)%elform /= ELFORM_HEX_ONE_POINT) s = s//' in place of '// &
              itoa(model%sections(sec)%elform)
          s = s//'), hourglass IHQ '//itoa(ihq)//' QM '//rtoa(qm)
        end if
      end select
    else
      select case (model%sections(sec)%elform)
      case (ELFORM_MEFEM)
        s = 'ME-FEM plane-strain triangle (ELFORM 43)'
      case (ELFORM_TRI_PLANE_STRAIN)
        s = 'standard plane-strain triangle (ELFORM 13)'
      end select
    end if
  end function formulation_name

  !> True for the solid ELFORMs computed as the one-point hexahedron (1, and the fully
  !> integrated 2, -1, -2 in its place).
  elemental logical function hexahedral_formulation(elform)
    integer, intent(in) :: elform        !< *SECTION_SOLID ELFORM
    hexahedral_formulation = elform == ELFORM_HEX_ONE_POINT .or. &
                             any(ELFORM_HEX_FULLY_INTEGRATED == elform)
  end function hexahedral_formulation

  !> The hourglass control of part p's one-point hexahedra: IHQ and QM of its *HOURGLASS
  !> (HGID), where that leaves IHQ 0 the default type; without one, *CONTROL_HOURGLASS's IHQ
  !> and QH; LS-DYNA's defaults where these are 0: IHQ 1 (viscous), QM 0.1. A fully
  !> integrated ELFORM (2, -1, -2) runs with IHQ 6, QM 1 (the elastic bending stiffness).
  subroutine part_hourglass(model, p, ihq, qm)
    type(model_t), intent(in) :: model   !< resolved model
    integer, intent(in) :: p             !< part index
    integer, intent(out) :: ihq          !< hourglass type, 1 to 10
    real(wp), intent(out) :: qm          !< hourglass coefficient
    integer, parameter :: DEFAULT_IHQ = 1
    real(wp), parameter :: DEFAULT_QM = 0.1_wp
    integer :: h
    h = model%parts(p)%hourglass
    if (model%parts(p)%section > 0) then
      if (any(ELFORM_HEX_FULLY_INTEGRATED == model%sections(model%parts(p)%section)%elform)) &
        then
        ihq = 6
        qm = 1.0_wp
        return
      end if
    end if
    if (h > 0) then
      ihq = model%hourglasses(h)%ihq
      qm = model%hourglasses(h)%qm
    else
      ihq = model%controls%ihq
      qm = model%controls%qh
    end if
    if (ihq == 0) ihq = DEFAULT_IHQ
    if (qm == 0.0_wp) qm = DEFAULT_QM
  end subroutine part_hourglass

  !> id is in the list (an unallocated list is empty).
  pure logical function listed(list, id)
    integer, allocatable, intent(in) :: list(:)   !< ids
    integer, intent(in) :: id                     !< the id looked for
    listed = .false.
    if (allocated(list)) listed = any(list == id)
  end function listed

end module mefem_model_resolve
