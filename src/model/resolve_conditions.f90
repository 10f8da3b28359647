!> Resolves the references of materials, sets, curves, boundary conditions, loads, initial
!> velocities, contacts, rigid walls and history outputs from user ids to 1-based indices,
!> and reports duplicate ids (materials, curves, sets of one kind).
!>
!> Every problem is reported as `file:line: *KEYWORD: message` at the record that holds the
!> reference, e.g. `deck.k:57: *BOUNDARY_SPC_SET: node set 12 is not defined`, all in one
!> pass. The maps of material and curve ids are returned for the part and output checks
!> done by the caller (model_resolve).
module mefem_resolve_conditions
  use mefem_kinds, only: wp
  use mefem_errors, only: input_error, warn, status_t
  use mefem_strings, only: itoa
  use mefem_deck_source, only: location
  use mefem_id_map, only: id_map_t, id_map_build, id_map_find, sort_with_index
  use mefem_vector_math, only: frame_from_vectors
  use mefem_model, only: model_t, source_t, SURFACE_SEGMENT_SET, SURFACE_PART, &
                         SURFACE_PART_SET, SURFACE_NODE_SET, SURFACE_ALL_PARTS, &
                         SURFACE_ALL_BUT_SET, &
                         ON_NODE, ON_NODE_SET, ON_PART, ON_ALL_NODES, &
                         FS_FROM_PARTS, contact_t, GENERAL_ALL, GENERAL_NODE, GENERAL_PART, &
                         RIGID_MERGE, RIGID_NODAL, &
                         GENERAL_SET, &
                         ON_PART_SET, ON_SEGMENT_SET, SET_NODE, SET_SEGMENT, SET_PART, &
                         MAT_PIECEWISE_LINEAR, MAT_RIGID, GENERAL_BOX, box_holds, &
                         coordinate_system_t, spc_t, SYSTEM_BY_POINTS, SYSTEM_BY_VECTORS, &
                         SET_SOLID, SET_SHELL, SET_KINDS, ELEM_SOLID, ELEM_SHELL, box_t, &
                         GENERAL_SEG
  use mefem_read_materials, only: material_keyword
  use mefem_read_sets, only: set_keyword
  use mefem_contact_surfaces, only: contact_surface_t, contact_parts_to_facets
  implicit none
  private

  public :: resolve_conditions, resolve_segment_sets

  character(len=1), parameter :: AXIS_NAMES(3) = ['X', 'Y', 'Z']   !< *LOAD_BODY_ suffixes
  !> *DEFINE_COORDINATE_ suffixes by system kind (SYSTEM_BY_POINTS, _VECTORS, _NODES)
  character(len=6), parameter :: SYSTEM_KIND(3) = ['SYSTEM', 'VECTOR', 'NODES ']

  !> Map of the ids of the sets of one kind to their positions in model%sets.
  type :: set_lookup_t
    type(id_map_t) :: map                  !< ids of the sets of this kind
    integer, allocatable :: position(:)    !< (n) index in model%sets of the k-th such set
  end type set_lookup_t

  !> Everything a reference may point to.
  type :: lookup_t
    type(id_map_t) :: nodes, parts, curves, materials, boxes, systems, vectors
    type(set_lookup_t) :: sets(SET_KINDS)  !< by SET_NODE, SET_SEGMENT, SET_PART, SET_SOLID,
                                           !< SET_SHELL
    logical, allocatable :: is_table(:)    !< (curve index) a *DEFINE_TABLE
  end type lookup_t

contains

  !> Resolve all references of the conditions; build the material and curve id maps.
  subroutine resolve_conditions(model, node_map, part_map, material_map, curve_map)
    type(model_t), intent(inout) :: model          !< the model read from the deck
    type(id_map_t), intent(in) :: node_map         !< node ids -> node indices
    type(id_map_t), intent(in) :: part_map         !< part ids -> part indices
    type(id_map_t), intent(out) :: material_map    !< material ids -> material indices
    type(id_map_t), intent(out) :: curve_map       !< curve ids -> curve indices
    type(lookup_t) :: look
    integer :: k
    integer, allocatable :: ids(:)
    call allocate_empty(model)
    ! curves and materials: maps and duplicates
    ids = [(model%curves(k)%id, k = 1, model%n_curves)]
    call id_map_build(ids, model%n_curves, curve_map)
    do k = 2, curve_map%n
      if (curve_map%ids(k) /= curve_map%ids(k-1)) cycle
      if (model%curves(curve_map%index(k))%is_table .or. &
          model%curves(curve_map%index(k-1))%is_table) then
        call report_duplicate(model%curves(curve_map%index(k))%src, &
            model%curves(curve_map%index(k-1))%src, &
            merge('*DEFINE_TABLE', '*DEFINE_CURVE', model%curves(curve_map%index(k))%is_table), &
            'curve or table (one id space)', curve_map%ids(k))
      else
        call report_duplicate(model%curves(curve_map%index(k))%src, &
            model%curves(curve_map%index(k-1))%src, '*DEFINE_CURVE', 'curve', curve_map%ids(k))
      end if
    end do
    ids = [(model%materials(k)%id, k = 1, model%n_materials)]
    call id_map_build(ids, model%n_materials, material_map)
    do k = 2, material_map%n
      if (material_map%ids(k) == material_map%ids(k-1)) call report_duplicate( &
          model%materials(material_map%index(k))%src, &
          model%materials(material_map%index(k-1))%src, &
          material_keyword(model%materials(material_map%index(k))%kind), 'material', &
          material_map%ids(k))
    end do
    look%nodes = node_map
    look%parts = part_map
    look%curves = curve_map
    look%is_table = [(model%curves(k)%is_table, k = 1, model%n_curves)]
    call resolve_tables(model, look)
    look%materials = material_map
    call map_without_duplicates([(model%boxes(k)%id, k = 1, model%n_boxes)], &
        [(model%boxes(k)%src, k = 1, model%n_boxes)], '*DEFINE_BOX', 'box', look%boxes)
    call map_without_duplicates([(model%vectors(k)%id, k = 1, model%n_vectors)], &
        [(model%vectors(k)%src, k = 1, model%n_vectors)], '*DEFINE_VECTOR', 'vector', &
        look%vectors)
    ids = [(model%systems(k)%id, k = 1, model%n_systems)]    ! (the keyword by the kind)
    call id_map_build(ids, model%n_systems, look%systems)
    do k = 2, look%systems%n
      if (look%systems%ids(k) == look%systems%ids(k-1)) call report_duplicate( &
          model%systems(look%systems%index(k))%src, &
          model%systems(look%systems%index(k-1))%src, '*DEFINE_COORDINATE_'// &
          trim(SYSTEM_KIND(model%systems(look%systems%index(k))%kind)), &
          'coordinate system', look%systems%ids(k))
    end do
    call resolve_coordinate_systems(model, look)
    call build_set_lookups(model, look)
    call resolve_materials(model, look)
    call resolve_sets(model, look)
    call resolve_constraints(model, look)
    call resolve_loads(model, look)
    call resolve_initial_velocities(model, look)
    call resolve_contacts(model, look)
    call resolve_outputs(model, look)
  end subroutine resolve_conditions

  !> Give every entity array a size so that empty models need no special cases.
  subroutine allocate_empty(model)
    type(model_t), intent(inout) :: model   !< the model
    if (.not. allocated(model%materials)) allocate(model%materials(0))
    if (.not. allocated(model%curves)) allocate(model%curves(0))
    if (.not. allocated(model%sets)) allocate(model%sets(0))
    if (.not. allocated(model%parts)) allocate(model%parts(0))
    if (.not. allocated(model%spcs)) allocate(model%spcs(0))
    if (.not. allocated(model%motions)) allocate(model%motions(0))
    if (.not. allocated(model%nodal_loads)) allocate(model%nodal_loads(0))
    if (.not. allocated(model%pressure_loads)) allocate(model%pressure_loads(0))
    if (.not. allocated(model%initial_velocities)) allocate(model%initial_velocities(0))
    if (.not. allocated(model%contacts)) allocate(model%contacts(0))
    if (.not. allocated(model%rigid_walls)) allocate(model%rigid_walls(0))
    if (.not. allocated(model%body_loads)) allocate(model%body_loads(0))
    if (.not. allocated(model%boxes)) allocate(model%boxes(0))
    if (.not. allocated(model%systems)) allocate(model%systems(0))
    if (.not. allocated(model%vectors)) allocate(model%vectors(0))
  end subroutine allocate_empty

  !> The id is in the list (an unallocated list holds none).
  pure logical function listed_id(list, id)
    integer, allocatable, intent(in) :: list(:)     !< ids
    integer, intent(in) :: id                       !< the id
    listed_id = .false.
    if (allocated(list)) listed_id = any(list == id)
  end function listed_id

  !> Resolve a box reference (BOXID); report it when undefined.
  subroutine resolve_box(look, id, index, where)
    type(lookup_t), intent(in) :: look              !< lookups
    integer, intent(in) :: id                       !< box id (> 0)
    integer, intent(out) :: index                   !< its index (0 when undefined)
    character(len=*), intent(in) :: where           !< "file:line: *KEYWORD"
    index = id_map_find(look%boxes, id)
    if (index == 0) call input_error(where, 'BOXID: box '//itoa(id)//' is not defined '// &
                                     '(*DEFINE_BOX)')
  end subroutine resolve_box

  !> "file:line: KEYWORD" of a record.
  function where_is(src, keyword) result(s)
    type(source_t), intent(in) :: src         !< where the record was read
    character(len=*), intent(in) :: keyword   !< its keyword
    character(len=:), allocatable :: s
    s = location(src%file, src%line)//': '//keyword
  end function where_is

  !> Report an id defined twice.
  subroutine report_duplicate(src, first_src, keyword, what, id)
    type(source_t), intent(in) :: src, first_src   !< this and the first definition
    character(len=*), intent(in) :: keyword        !< keyword of this definition
    character(len=*), intent(in) :: what           !< 'curve', 'node set' ...
    integer, intent(in) :: id                      !< the id
    call input_error(where_is(src, keyword), what//' id '//itoa(id)// &
        ' is defined twice (first at '//location(first_src%file, first_src%line)//')')
  end subroutine report_duplicate

  !> The id map of one kind of record, each id given twice reported at its later definition.
  subroutine map_without_duplicates(ids, sources, keyword, what, map)
    integer, intent(in) :: ids(:)                  !< the records' ids
    type(source_t), intent(in) :: sources(:)       !< where each was read
    character(len=*), intent(in) :: keyword        !< the keyword that defines them
    character(len=*), intent(in) :: what           !< 'box', 'vector', ...
    type(id_map_t), intent(out) :: map             !< ids -> record indices
    integer :: k
    call id_map_build(ids, size(ids), map)
    do k = 2, map%n
      if (map%ids(k) == map%ids(k-1)) call report_duplicate(sources(map%index(k)), &
          sources(map%index(k-1)), keyword, what, map%ids(k))
    end do
  end subroutine map_without_duplicates

  !> Per-kind maps of set ids, with duplicate ids reported.
  subroutine build_set_lookups(model, look)
    type(model_t), intent(in) :: model        !< the model
    type(lookup_t), intent(inout) :: look     !< lookups, sets filled in
    integer :: kind, s, n, k
    integer, allocatable :: ids(:)
    do kind = 1, SET_KINDS
      n = count(model%sets(1:model%n_sets)%kind == kind)
      allocate(ids(n), look%sets(kind)%position(n))
      n = 0
      do s = 1, model%n_sets
        if (model%sets(s)%kind /= kind) cycle
        n = n + 1
        ids(n) = model%sets(s)%id
        look%sets(kind)%position(n) = s
      end do
      call id_map_build(ids, n, look%sets(kind)%map)
      associate (map => look%sets(kind)%map, position => look%sets(kind)%position)
        do k = 2, map%n
          if (map%ids(k) == map%ids(k-1)) call report_duplicate( &
              model%sets(position(map%index(k)))%src, model%sets(position(map%index(k-1)))%src, &
              set_keyword(kind), set_name(kind), map%ids(k))
        end do
      end associate
      deallocate(ids)
    end do
  end subroutine build_set_lookups

  !> Index in model%sets of the set of a kind with an id (0 if none).
  integer function find_set(look, kind, id)
    type(lookup_t), intent(in) :: look   !< lookups
    integer, intent(in) :: kind, id      !< SET_* kind and set id
    integer :: k
    find_set = 0
    k = id_map_find(look%sets(kind)%map, id)
    if (k > 0) find_set = look%sets(kind)%position(k)
  end function find_set

  !> 'node set', 'part set' or 'segment set'.
  function set_name(kind) result(s)
    integer, intent(in) :: kind   !< SET_* kind
    character(len=:), allocatable :: s
    select case (kind)
    case (SET_NODE)
      s = 'node set'
    case (SET_PART)
      s = 'part set'
    case (SET_SOLID)
      s = 'solid set'
    case (SET_SHELL)
      s = 'shell set'
    case default
      s = 'segment set'
    end select
  end function set_name

  !> Index of a target of an ON_* kind (0 when undefined; ON_ALL_NODES gives 0 too).
  integer function find_target(look, kind, id)
    type(lookup_t), intent(in) :: look   !< lookups
    integer, intent(in) :: kind, id      !< ON_* kind and id
    select case (kind)
    case (ON_NODE)
      find_target = id_map_find(look%nodes, id)
    case (ON_NODE_SET)
      find_target = find_set(look, SET_NODE, id)
    case (ON_PART)
      find_target = id_map_find(look%parts, id)
    case (ON_PART_SET)
      find_target = find_set(look, SET_PART, id)
    case (ON_SEGMENT_SET)
      find_target = find_set(look, SET_SEGMENT, id)
    case default
      find_target = 0
    end select
  end function find_target

  !> 'node', 'node set', 'part', 'part set' or 'segment set' for an ON_* kind.
  function target_name(kind) result(s)
    integer, intent(in) :: kind   !< ON_* kind
    character(len=:), allocatable :: s
    select case (kind)
    case (ON_NODE)
      s = 'node'
    case (ON_NODE_SET)
      s = 'node set'
    case (ON_PART)
      s = 'part'
    case (ON_PART_SET)
      s = 'part set'
    case (ON_SEGMENT_SET)
      s = 'segment set'
    case default
      s = 'all nodes'
    end select
  end function target_name

  !> Resolve a target reference; report it when undefined.
  subroutine resolve_target(look, kind, id, index, where, prefix)
    type(lookup_t), intent(in) :: look              !< lookups
    integer, intent(in) :: kind, id                 !< ON_* kind and id
    integer, intent(out) :: index                   !< its index (0 when undefined)
    character(len=*), intent(in) :: where           !< "file:line: *KEYWORD"
    character(len=*), intent(in), optional :: prefix  !< text before the message
    index = 0
    if (kind == ON_ALL_NODES) return
    index = find_target(look, kind, id)
    if (index > 0) return
    if (present(prefix)) then
      call input_error(where, prefix//target_name(kind)//' '//itoa(id)//' is not defined')
    else
      call input_error(where, target_name(kind)//' '//itoa(id)//' is not defined')
    end if
  end subroutine resolve_target

  !> Resolve a curve reference; report it when undefined.
  subroutine resolve_curve(look, id, index, where, field)
    type(lookup_t), intent(in) :: look              !< lookups
    integer, intent(in) :: id                       !< curve id
    integer, intent(out) :: index                   !< its index (0 when undefined)
    character(len=*), intent(in) :: where           !< "file:line: *KEYWORD"
    character(len=*), intent(in) :: field           !< prefix naming the field
    index = id_map_find(look%curves, id)
    if (index == 0) then
      call input_error(where, field//'curve '//itoa(id)//' is not defined')
    else if (look%is_table(index)) then
      call input_error(where, field//'id '//itoa(id)//' is a table (*DEFINE_TABLE); a curve '// &
                       'is needed here')
      index = 0
    end if
  end subroutine resolve_curve

  !> The axes of every coordinate system (reference configuration) and the global direction
  !> of every vector. A system by points in another system (CIDL) waits for that one; a
  !> chain that never resolves (undefined or circular CIDL) is reported.
  subroutine resolve_coordinate_systems(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups (nodes, systems)
    real(wp) :: p(3, 3)
    integer :: k, j, m, pass, n_done, n_node
    logical :: ready
    character(len=:), allocatable :: where
    do pass = 1, model%n_systems
      n_done = 0
      do k = 1, model%n_systems
        associate (system => model%systems(k))
          if (system%resolved) cycle
          where = where_is(system%src, '*DEFINE_COORDINATE_'//trim(SYSTEM_KIND(system%kind)))
          p = system%points
          select case (system%kind)
          case (SYSTEM_BY_POINTS)
            ready = system%reference_id == 0
            if (.not. ready) then
              j = id_map_find(look%systems, system%reference_id)
              if (j == 0) then
                call input_error(where, 'coordinate system '//itoa(system%id)//': CIDL: '// &
                    'coordinate system '//itoa(system%reference_id)//' is not defined')
                system%resolved = .true.
                cycle
              end if
              ready = model%systems(j)%resolved
              if (.not. ready) cycle
              p = spread(model%systems(j)%origin, 2, 3) + matmul(model%systems(j)%axes, p)
            end if
            call set_axes(system, p(:, 1), p(:, 2) - p(:, 1), p(:, 3) - p(:, 1), where)
          case (SYSTEM_BY_VECTORS)
            call set_axes(system, [0.0_wp, 0.0_wp, 0.0_wp], p(:, 1), p(:, 2), where)
          case default
            n_node = 0
            do j = 1, 3
              p(:, j) = 0.0_wp
              if (id_map_find(look%nodes, system%node_ids(j)) == 0) then
                call input_error(where, 'coordinate system '//itoa(system%id)//': node '// &
                                 itoa(system%node_ids(j))//' (N'//itoa(j)//') is not defined')
              else
                n_node = n_node + 1
                system%nodes(j) = id_map_find(look%nodes, system%node_ids(j))
                p(:, j) = model%nodes%x(:, system%nodes(j))
              end if
            end do
            if (n_node == 3) call set_axes(system, p(:, 1), p(:, 2) - p(:, 1), &
                                           p(:, 3) - p(:, 1), where)
          end select
          system%resolved = .true.
          n_done = n_done + 1
        end associate
      end do
      if (n_done == 0) exit
    end do
    do k = 1, model%n_systems
      if (.not. model%systems(k)%resolved) call input_error(where_is(model%systems(k)%src, &
          '*DEFINE_COORDINATE_SYSTEM'), 'coordinate system '//itoa(model%systems(k)%id)// &
          ': CIDL: the systems refer to each other in a circle')
    end do
    do k = 1, model%n_vectors
      associate (vector => model%vectors(k))
        where = where_is(vector%src, '*DEFINE_VECTOR')
        if (vector%tail_node > 0) then            ! _NODES: from NODET to NODEH
          where = where_is(vector%src, '*DEFINE_VECTOR_NODES')
          n_node = 0
          do j = 1, 2
            m = id_map_find(look%nodes, merge(vector%tail_node, vector%head_node, j == 1))
            if (m == 0) then
              call input_error(where, 'vector '//itoa(vector%id)//': node '// &
                  itoa(merge(vector%tail_node, vector%head_node, j == 1))//' ('// &
                  trim(merge('NODET', 'NODEH', j == 1))//') is not defined')
              cycle
            end if
            n_node = n_node + 1
            if (j == 1) vector%tail = model%nodes%x(:, m)
            if (j == 2) vector%head = model%nodes%x(:, m)
          end do
          if (n_node < 2) cycle
        end if
        vector%direction = vector%head - vector%tail
        if (.not. norm2(vector%direction) > 0.0_wp) then
          call input_error(where, 'vector '//itoa(vector%id)//': head and tail coincide (a '// &
                           'vector of length 0 has no direction)')
          cycle
        end if
        vector%direction = vector%direction/norm2(vector%direction)
        if (vector%system_id > 0) then
          j = find_system(look, vector%system_id, where, 'vector '//itoa(vector%id)//': CID: ')
          if (j > 0) vector%direction = matmul(model%systems(j)%axes, vector%direction)
        end if
      end associate
    end do
  end subroutine resolve_coordinate_systems

  !> Axes of a system from its origin, its first axis' direction and a vector in the plane of
  !> that axis and the next (mefem_vector_math frame_from_vectors); a degenerate definition
  !> (zero axis, or the in-plane vector parallel to it) is reported.
  subroutine set_axes(system, origin, along, in_plane, where)
    type(coordinate_system_t), intent(inout) :: system   !< the system
    real(wp), intent(in) :: origin(3), along(3), in_plane(3)  !< global
    character(len=*), intent(in) :: where                !< "file:line: *KEYWORD"
    logical :: ok
    system%origin = origin
    if (.not. norm2(along) > 0.0_wp .or. .not. norm2(in_plane) > 0.0_wp) then
      call input_error(where, 'coordinate system '//itoa(system%id)//': its x axis or its '// &
                       'in-plane vector has length 0')
      return
    end if
    call frame_from_vectors(system%first_axis, along, in_plane, system%axes, ok)
    if (.not. ok) call input_error(where, 'coordinate system '//itoa(system%id)//': the '// &
        'point (or vector) of the x-y plane lies on the x axis: the plane is undefined')
  end subroutine set_axes

  !> Index of coordinate system id (resolved); reported and 0 when undefined.
  integer function find_system(look, id, where, field)
    type(lookup_t), intent(in) :: look              !< lookups
    integer, intent(in) :: id                       !< system id
    character(len=*), intent(in) :: where           !< "file:line: *KEYWORD"
    character(len=*), intent(in) :: field           !< prefix naming the field
    find_system = id_map_find(look%systems, id)
    if (find_system == 0) call input_error(where, field//'coordinate system '//itoa(id)// &
                                           ' is not defined (*DEFINE_COORDINATE_...)')
  end function find_system

  !> An SPC in a local system: each fixed local translation whose axis is a global axis
  !> (to round-off) fixes that global dof; the others become skew constraints (their
  !> directions and local axes kept; in a moving system every fixed axis does); all three
  !> fixed fix all three global dofs.
  subroutine local_spc(spc, axes)
    type(spc_t), intent(inout) :: spc               !< the SPC (dof: local flags)
    real(wp), intent(in) :: axes(3, 3)              !< the system's global axes
    !> |component| above which a unit axis is the global axis
    real(wp), parameter :: ALIGNED = 1.0_wp - 1.0e-12_wp
    logical :: local(3)
    integer :: k, j
    local = spc%dof(1:3)
    spc%dof(1:3) = .false.
    spc%n_skew = 0
    if (all(local)) then
      spc%dof(1:3) = .true.
      return
    end if
    do k = 1, 3
      if (.not. local(k)) cycle
      j = maxloc(abs(axes(:, k)), dim=1)
      if (abs(axes(j, k)) >= ALIGNED .and. spc%moving_system == 0) then
        spc%dof(j) = .true.
      else                                        ! (a moving system's axes turn: skew)
        spc%n_skew = spc%n_skew + 1
        spc%skew(:, spc%n_skew) = axes(:, k)
        spc%skew_axis(spc%n_skew) = k
      end if
    end do
  end subroutine local_spc

  !> The curves of every *DEFINE_TABLE: by LCID, or, for a blank LCID, the curves defined
  !> right after the table in deck order (the k-th blank takes the k-th); each must be a
  !> curve, not a table.
  subroutine resolve_tables(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups (curves)
    integer :: k, j, next, index
    character(len=:), allocatable :: where
    do k = 1, model%n_curves
      associate (table => model%curves(k))
        if (.not. table%is_table) cycle
        where = where_is(table%src, '*DEFINE_TABLE')
        allocate(table%members(table%n))
        table%members = 0
        next = table%follows
        do j = 1, table%n
          if (table%member_ids(j) > 0) then
            index = id_map_find(look%curves, table%member_ids(j))
            if (index == 0) then
              call input_error(where, 'table '//itoa(table%id)//': curve '// &
                  itoa(table%member_ids(j))//' (value '//itoa(j)//') is not defined')
              cycle
            end if
          else
            index = next
            next = next + 1
            if (index > model%n_curves) then
              call input_error(where, 'table '//itoa(table%id)//': value '//itoa(j)// &
                  ' has no LCID and no *DEFINE_CURVE follows the table for it (give LCID, or '// &
                  'the curves right after the table, one per value)')
              cycle
            end if
          end if
          if (model%curves(index)%is_table) then
            call input_error(where, 'table '//itoa(table%id)//': value '//itoa(j)// &
                ' refers to table '//itoa(model%curves(index)%id)//'; a curve is needed')
            cycle
          end if
          table%members(j) = index
        end do
      end associate
    end do
  end subroutine resolve_tables

  !> Curves of *MAT_024 (LCSS, LCSR).
  subroutine resolve_materials(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    integer :: m, k
    character(len=:), allocatable :: where
    do m = 1, model%n_materials
      associate (mat => model%materials(m))
        if (mat%kind /= MAT_PIECEWISE_LINEAR) cycle
        where = where_is(mat%src, material_keyword(mat%kind))
        if (mat%lcss > 0) then
          k = id_map_find(look%curves, mat%lcss)
          if (k == 0) then
            call input_error(where, 'material '//itoa(mat%id)//': LCSS curve '// &
                             itoa(mat%lcss)//' is not defined')
          else if (look%is_table(k)) then
            ! a table of hardening curves by strain rate (its values: ln(rate) when the first
            ! is negative); C, P and LCSR then do not apply
            mat%lcss_table = k
            mat%lcss_curve = model%curves(k)%members(1)
            mat%lcss_log_rates = model%curves(k)%t(1) < 0.0_wp
            if (any(model%curves(k)%members == 0)) mat%lcss_table = 0
            if (mat%cowper_c > 0.0_wp .or. mat%lcsr > 0) call warn(where//': material '// &
                itoa(mat%id)//': C, P and LCSR are ignored: the table LCSS '// &
                itoa(mat%lcss)//' gives the rate dependence')
            if (mat%vp == 1.0_wp) call warn(where//': material '//itoa(mat%id)//': VP = 1 '// &
                'with the table LCSS '//itoa(mat%lcss)//' is computed as VP = 0: the curves '// &
                'are taken at the total strain rate')
          else
            mat%lcss_curve = k
          end if
        end if
        if (mat%lcsr > 0) call resolve_curve(look, mat%lcsr, mat%lcsr_curve, where, &
            'material '//itoa(mat%id)//': LCSR ')
      end associate
    end do
    ! *MAT_ADD_EROSION: its criteria join its material
    do m = 1, model%n_add_erosions
      associate (ae => model%add_erosions(m))
        where = where_is(ae%src, '*MAT_ADD_EROSION')
        k = id_map_find(look%materials, ae%material_id)
        if (k == 0) then
          if (.not. listed_id(model%rejected_material_ids, ae%material_id)) call input_error( &
              where, 'material '//itoa(ae%material_id)//' (MID) is not defined')
          cycle
        end if
        associate (mat => model%materials(k))
          if (mat%kind == MAT_RIGID) then
            call input_error(where, 'material '//itoa(mat%id)//' is *MAT_RIGID: a rigid '// &
                             'body does not erode')
          else if (mat%add_erosion) then
            call input_error(where, 'material '//itoa(mat%id)//' has a *MAT_ADD_EROSION '// &
                             'already')
          else
            mat%add_erosion = .true.
            mat%erosion_limit = ae%limit
            mat%erosion_used = ae%limit /= ae%exclusion .and. ae%limit /= 0.0_wp
            mat%erosion_conditions = ae%conditions
            if (.not. any(mat%erosion_used)) call warn(where//': material '// &
                itoa(mat%id)//': every criterion is 0 or EXCL: nothing erodes')
          end if
        end associate
      end associate
    end do
    if (model%controls%lctm > 0) call resolve_curve(look, model%controls%lctm, &
        model%controls%lctm_curve, where_is(model%controls%lctm_src, '*CONTROL_TIMESTEP'), &
        'LCTM ')
  end subroutine resolve_materials

  !> Members of every set: node ids, part ids, segment node ids -> indices.
  subroutine resolve_sets(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    type(id_map_t) :: element_map(SET_SOLID:SET_SHELL)   !< element ids of each id space
    integer :: s, i
    character(len=:), allocatable :: where, member
    do s = 1, model%n_sets
      associate (set => model%sets(s))
        if (.not. allocated(set%member_ids)) allocate(set%member_ids(0))
        if (set%general) cycle                      ! (after the others: they may name them)
        ! _GENERATE: "all defined ids between B and E" (LS-DYNA), in ascending id order,
        ! each once; an empty set is an error
        if (set%generated .and. (set%kind == SET_SOLID .or. set%kind == SET_SHELL)) then
          call ids_in_ranges(element_ids(set%kind), set%member_ids, set%members)
          set%member_ids = model%elements%id(set%members)
          set%n = size(set%members)
          if (set%n == 0) call input_error(where_is(set%src, set_keyword(set%kind)), &
              set_name(set%kind)//' '//itoa(set%id)//': no '//element_kind(set%kind)// &
              ' element of its ranges is defined')
          cycle
        else if (set%generated) then
          call ids_in_ranges(model%nodes%id(1:model%nodes%n), set%member_ids, set%members)
          set%member_ids = model%nodes%id(set%members)
          set%n = size(set%members)
          if (set%n == 0) call input_error(where_is(set%src, set_keyword(set%kind)), &
              set_name(set%kind)//' '//itoa(set%id)//': no node of its ranges is defined')
          cycle
        end if
        if (allocated(set%members)) deallocate(set%members)
        allocate(set%members(size(set%member_ids)))
        set%members = 0
        where = where_is(set%src, set_keyword(set%kind))
        member = merge('part', 'node', set%kind == SET_PART)
        if (set%kind == SET_SOLID .or. set%kind == SET_SHELL) then
          member = element_kind(set%kind)//' element'
          if (.not. allocated(element_map(set%kind)%ids)) call id_map_build( &
              element_ids(set%kind), model%elements%n, element_map(set%kind))
        end if
        do i = 1, size(set%member_ids)
          if (set%kind == SET_PART) then
            set%members(i) = id_map_find(look%parts, set%member_ids(i))
          else if (set%kind == SET_SOLID .or. set%kind == SET_SHELL) then
            set%members(i) = id_map_find(element_map(set%kind), set%member_ids(i))
          else
            set%members(i) = id_map_find(look%nodes, set%member_ids(i))
          end if
          if (set%members(i) == 0) call input_error(where, &
              set_name(set%kind)//' '//itoa(set%id)//': '//member//' '// &
              itoa(set%member_ids(i))//' is not defined')
        end do
      end associate
    end do
    do s = 1, model%n_sets      ! (segment sets after the elements: resolve_segment_sets)
      if (model%sets(s)%general .and. model%sets(s)%kind /= SET_SEGMENT) &
        call resolve_general_set(model, look, s)
    end do

  contains

    !> The ids of the solid (SET_SOLID) or shell (SET_SHELL) elements, the others -1 (no
    !> element id is negative), in element order.
    function element_ids(kind) result(ids)
      integer, intent(in) :: kind                   !< SET_SOLID or SET_SHELL
      integer, allocatable :: ids(:)
      ids = merge(model%elements%id(1:model%elements%n), -1, &
                  model%elements%keyword(1:model%elements%n) == &
                  merge(ELEM_SOLID, ELEM_SHELL, kind == SET_SOLID))
    end function element_ids

    !> 'solid' or 'shell'.
    function element_kind(kind) result(name)
      integer, intent(in) :: kind                   !< SET_SOLID or SET_SHELL
      character(len=5) :: name
      name = merge('solid', 'shell', kind == SET_SOLID)
    end function element_kind

  end subroutine resolve_sets

  !> *SET_SEGMENT_GENERAL (after the elements are resolved): each set's entries applied in
  !> order to a mask over candidate segments, the exterior faces of solids (and shells, 2D
  !> edges) as contact surfaces take them, oriented outward: ALL the model's exterior; PART
  !> each part's own exterior; BOX the model's exterior segments whose nodes all lie in the box
  !> (reference positions, faces included); SEG one segment N1 .. N4; negative codes remove.
  !> The members: the segments left, 4 node indices each (a triangle N4 = N3, a 2D line N1 N2
  !> N2 N2), in the candidates' order.
  subroutine resolve_segment_sets(model, node_map, part_map)
    type(model_t), intent(inout) :: model          !< the model (elements resolved)
    type(id_map_t), intent(in) :: node_map         !< node ids -> indices
    type(id_map_t), intent(in) :: part_map         !< part ids -> indices
    integer, allocatable :: pool(:,:), grown(:,:), ids(:)
    logical, allocatable :: in_set(:), selected(:)
    type(id_map_t) :: box_map
    type(contact_surface_t) :: exterior
    integer :: s, k, code, n, i, id, index, n_pool, n_exterior, c, n_bad
    logical :: add
    character(len=:), allocatable :: where, who
    if (.not. any(model%sets(1:model%n_sets)%general .and. &
                  model%sets(1:model%n_sets)%kind == SET_SEGMENT)) return
    ids = [(model%boxes(k)%id, k = 1, model%n_boxes)]
    call id_map_build(ids, model%n_boxes, box_map)
    allocate(selected(model%n_parts), pool(4, 64))
    selected = .true.
    call exterior_facets(exterior)                 ! the model's exterior: candidates 1 .. n
    n_pool = 0
    do k = 1, exterior%nfacet
      call add_to_pool(facet_nodes(exterior, k))
    end do
    n_exterior = n_pool
    do s = 1, model%n_sets
      associate (set => model%sets(s))
        if (.not. (set%general .and. set%kind == SET_SEGMENT)) cycle
        where = where_is(set%src, '*SET_SEGMENT_GENERAL')
        who = 'segment set '//itoa(set%id)//': '
        allocate(in_set(n_pool))
        in_set = .false.
        n_bad = 0
        k = 1
        do while (k <= size(set%member_ids))
          code = set%member_ids(k)
          n = set%member_ids(k + 1)
          add = code > 0
          select case (abs(code))
          case (GENERAL_ALL)
            in_set(1:n_exterior) = add
          case (GENERAL_PART)
            do i = 1, n
              id = set%member_ids(k + 1 + i)
              index = id_map_find(part_map, id)
              if (index == 0) then
                call input_error(where, who//'part '//itoa(id)//' is not defined')
                n_bad = n_bad + 1
                cycle
              end if
              selected = .false.
              selected(index) = .true.
              call exterior_facets(exterior)       ! this part's own exterior
              do c = 1, exterior%nfacet
                call mark(facet_nodes(exterior, c), add)
              end do
            end do
          case (GENERAL_BOX)
            do i = 1, n
              id = set%member_ids(k + 1 + i)
              index = id_map_find(box_map, id)
              if (index == 0) then
                call input_error(where, who//'BOX: box '//itoa(id)//' is not defined '// &
                                 '(*DEFINE_BOX)')
                n_bad = n_bad + 1
                cycle
              end if
              do c = 1, n_exterior
                if (all(box_holds_nodes(model%boxes(index), pool(:, c)))) in_set(c) = add
              end do
            end do
          case (GENERAL_SEG)
            block
              integer :: nodes(4), a
              do a = 1, 4
                nodes(a) = id_map_find(node_map, set%member_ids(k + 1 + a))
                if (nodes(a) == 0 .and. .not. any(set%member_ids(k + 2:k + a) == &
                                                  set%member_ids(k + 1 + a))) then
                  call input_error(where, who//'SEG: node '// &
                                   itoa(set%member_ids(k + 1 + a))//' is not defined')
                  n_bad = n_bad + 1
                end if
              end do
              if (all(nodes > 0)) call mark(nodes, add)
            end block
          end select
          k = k + 2 + n
        end do
        set%n = count(in_set(1:n_pool))
        if (set%n == 0 .and. n_bad == 0) call input_error(where, who//'no segment is left '// &
                                                          'in the set')
        set%members = reshape(pool(:, pack([(c, c = 1, n_pool)], in_set(1:n_pool))), &
                              [4*set%n])
        set%member_ids = model%nodes%id(set%members)
        set%general = .false.
        deallocate(in_set)
      end associate
    end do

  contains

    !> The exterior facets of the parts selected (contact_surfaces' rule).
    subroutine exterior_facets(surface)
      type(contact_surface_t), intent(out) :: surface  !< the facets
      type(status_t) :: status
      call contact_parts_to_facets(model, selected, surface, status, 'segment set')
    end subroutine exterior_facets

    !> Facet k of a surface as a segment's 4 nodes (N4 = N3 for a triangle; 2D: N1 N2 N2 N2).
    function facet_nodes(surface, k) result(nodes)
      type(contact_surface_t), intent(in) :: surface   !< the facets
      integer, intent(in) :: k                         !< which
      integer :: nodes(4), a
      nodes = surface%facets(:, k)
      do a = surface%nvertex(k) + 1, 4
        nodes(a) = nodes(surface%nvertex(k))
      end do
    end function facet_nodes

    !> A candidate segment (a new one at the end of the pool).
    subroutine add_to_pool(nodes)
      integer, intent(in) :: nodes(4)               !< its nodes
      if (n_pool == size(pool, 2)) then
        allocate(grown(4, 2*n_pool))
        grown(:, 1:n_pool) = pool(:, 1:n_pool)
        call move_alloc(grown, pool)
      end if
      n_pool = n_pool + 1
      pool(:, n_pool) = nodes
    end subroutine add_to_pool

    !> Put a segment in the set (add) or take it out: the candidate with the same nodes, or a
    !> new candidate (its orientation as given).
    subroutine mark(nodes, add)
      integer, intent(in) :: nodes(4)               !< the segment's nodes
      logical, intent(in) :: add                    !< put in (true) or take out
      logical, allocatable :: longer(:)
      integer :: c
      do c = 1, n_pool
        if (same_segment(pool(:, c), nodes)) then
          in_set(c) = add
          return
        end if
      end do
      if (.not. add) return
      call add_to_pool(nodes)
      allocate(longer(n_pool))
      longer(1:n_pool - 1) = in_set(1:n_pool - 1)
      longer(n_pool) = .true.
      call move_alloc(longer, in_set)
    end subroutine mark

    !> The nodes of a segment all inside a box.
    function box_holds_nodes(box, nodes) result(inside)
      type(box_t), intent(in) :: box                 !< the box
      integer, intent(in) :: nodes(4)                !< the segment's nodes
      logical :: inside(4)
      integer :: a
      do a = 1, 4
        inside(a) = box_holds(box, model%nodes%x(:, nodes(a)))
      end do
    end function box_holds_nodes

  end subroutine resolve_segment_sets

  !> Two segments with the same nodes (in any order).
  pure logical function same_segment(a, b)
    integer, intent(in) :: a(4), b(4)               !< the segments' nodes
    integer :: k
    same_segment = .true.
    do k = 1, 4
      same_segment = same_segment .and. any(b == a(k)) .and. any(a == b(k))
    end do
  end function same_segment

  !> *SET_NODE_GENERAL set s: its entries (GENERAL_* code, count, ids) applied in order to a
  !> mask over the nodes (negative codes remove), the members the nodes left, ascending; every
  !> id named must exist (a node set named must be defined before it if it is general too).
  subroutine resolve_general_set(model, look, s)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    integer, intent(in) :: s                  !< the set
    logical, allocatable :: mask(:), part_nodes(:)
    integer :: k, code, n, i, id, index, e, a, n_items
    logical :: add, parts
    character(len=:), allocatable :: where, who
    associate (set => model%sets(s))
      parts = set%kind == SET_PART
      if (parts) then
        where = where_is(set%src, '*SET_PART_GENERAL')
        who = 'part set '//itoa(set%id)//': '
        n_items = model%n_parts
      else
        where = where_is(set%src, '*SET_NODE_GENERAL')
        who = 'node set '//itoa(set%id)//': '
        n_items = model%nodes%n
      end if
      allocate(mask(n_items))
      mask = .false.
      k = 1
      do while (k <= size(set%member_ids))
        code = set%member_ids(k)
        n = set%member_ids(k + 1)
        add = code > 0
        if (abs(code) == GENERAL_ALL) mask = add
        do i = 1, n
          id = set%member_ids(k + 1 + i)
          select case (abs(code))
          case (GENERAL_NODE)
            index = id_map_find(look%nodes, id)
            if (index == 0) then
              call input_error(where, who//'node '//itoa(id)//' is not defined')
            else
              mask(index) = add
            end if
          case (GENERAL_PART)
            index = id_map_find(look%parts, id)
            if (index == 0) then
              call input_error(where, who//'part '//itoa(id)//' is not defined')
              cycle
            end if
            if (parts) then
              mask(index) = add
              cycle
            end if
            if (.not. allocated(part_nodes)) allocate(part_nodes(model%nodes%n))
            part_nodes = .false.
            do e = 1, model%elements%n
              if (model%elements%part_id(e) /= id) cycle
              do a = 1, 8
                if (model%elements%node_ids(a, e) == 0) cycle
                index = id_map_find(look%nodes, model%elements%node_ids(a, e))
                if (index > 0) part_nodes(index) = .true.
              end do
            end do
            where (part_nodes) mask = add
          case (GENERAL_SET)
            index = find_set(id)
            if (index == 0) then
              call input_error(where, who//trim(merge('part set', 'node set', parts))//' '// &
                  itoa(id)//' is not defined (or is a general set defined after this one)')
            else
              do a = 1, size(model%sets(index)%members)
                if (model%sets(index)%members(a) > 0) mask(model%sets(index)%members(a)) = add
              end do
            end if
          case (GENERAL_BOX)
            index = id_map_find(look%boxes, id)
            if (index == 0) then
              call input_error(where, who//'box '//itoa(id)//' is not defined (*DEFINE_BOX)')
              cycle
            end if
            do a = 1, model%nodes%n
              if (box_holds(model%boxes(index), model%nodes%x(:, a))) mask(a) = add
            end do
          end select
        end do
        k = k + 2 + n
      end do
      set%members = pack([(i, i = 1, n_items)], mask)
      if (parts) then
        set%member_ids = model%parts(set%members)%id
      else
        set%member_ids = model%nodes%id(set%members)
      end if
      set%n = size(set%members)
      set%general = .false.                     ! (resolved: an ordinary set now)
      if (set%n == 0) call input_error(where, who//'its entries leave no '// &
                                       trim(merge('part', 'node', parts)))
    end associate
  contains
    !> A resolved set of the same kind by id (0: none, or a general one not resolved yet).
    integer function find_set(set_id)
      integer, intent(in) :: set_id           !< the id
      integer :: m
      find_set = 0
      do m = 1, model%n_sets
        if (model%sets(m)%id /= set_id .or. model%sets(m)%kind /= model%sets(s)%kind) cycle
        if (model%sets(m)%general) cycle
        find_set = m
      end do
    end function find_set
  end subroutine resolve_general_set

  !> The items (nodes, elements) whose ids lie in any of the ranges (B1 E1 B2 E2 ...), each
  !> once, in ascending id order: the ranges sorted and merged, each item's id found by
  !> bisection (time n log(ranges), memory of the items found).
  subroutine ids_in_ranges(all_ids, ranges, members)
    integer, intent(in) :: all_ids(:)                !< ids of the items (negative: none)
    integer, intent(in) :: ranges(:)                 !< (2 * ranges) B E pairs
    integer, allocatable, intent(out) :: members(:)  !< item indices
    integer, allocatable :: b(:), e(:), ids(:)
    integer :: nr, k, m, node, lo, hi, mid
    logical, allocatable :: inside(:)
    nr = size(ranges)/2
    allocate(b(nr), e(nr))
    b(:) = ranges(1:2*nr:2)
    e(:) = ranges(2:2*nr:2)
    call sort_with_index(b, e)
    m = 0                                          ! merge overlapping or touching ranges
    do k = 1, nr
      if (m > 0) then
        if (b(k) <= e(m) + 1) then
          e(m) = max(e(m), e(k))
          cycle
        end if
      end if
      m = m + 1
      b(m) = b(k)
      e(m) = e(k)
    end do
    allocate(inside(size(all_ids)))
    do node = 1, size(all_ids)
      lo = 1                                       ! last range with b <= id
      hi = m
      inside(node) = .false.
      if (m == 0) cycle
      if (all_ids(node) < b(1)) cycle
      do while (lo < hi)
        mid = (lo + hi + 1)/2
        if (b(mid) <= all_ids(node)) then
          lo = mid
        else
          hi = mid - 1
        end if
      end do
      inside(node) = all_ids(node) <= e(lo)
    end do
    members = pack([(node, node = 1, size(all_ids))], inside)
    ids = all_ids(members)
    call sort_with_index(ids, members)
  end subroutine ids_in_ranges

  !> SPCs and prescribed motions: targets, curves, rigid parts.
  subroutine resolve_constraints(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    integer :: k, m
    character(len=:), allocatable :: where
    do k = 1, model%n_spcs
      associate (spc => model%spcs(k))
        where = where_is(spc%src, trim(merge('*BOUNDARY_SPC_SET ', '*BOUNDARY_SPC_NODE', &
                                             spc%target_kind == ON_NODE_SET)))
        call resolve_target(look, spc%target_kind, spc%target_id, spc%target, where)
        if (spc%cid > 0) then
          m = find_system(look, spc%cid, where, 'CID: ')
          if (m > 0) then
            if (model%systems(m)%moving) spc%moving_system = m
            call local_spc(spc, model%systems(m)%axes)
          end if
        end if
      end associate
    end do
    do k = 1, model%n_motions
      associate (motion => model%motions(k))
        select case (motion%target_kind)
        case (ON_NODE)
          where = where_is(motion%src, '*BOUNDARY_PRESCRIBED_MOTION_NODE')
        case (ON_NODE_SET)
          where = where_is(motion%src, '*BOUNDARY_PRESCRIBED_MOTION_SET')
        case default
          where = where_is(motion%src, '*BOUNDARY_PRESCRIBED_MOTION_RIGID')
        end select
        call resolve_target(look, motion%target_kind, motion%target_id, motion%target, where)
        call resolve_curve(look, motion%curve_id, motion%curve, where, '')
        if (motion%target_kind == ON_PART .and. motion%target > 0) then
          m = id_map_find(look%materials, model%parts(motion%target)%material_id)
          if (m > 0) then
            if (model%materials(m)%kind /= MAT_RIGID) call input_error(where, 'part '// &
                itoa(motion%target_id)//' is not rigid (its material '// &
                itoa(model%materials(m)%id)//' is not *MAT_RIGID); prescribe the motion of '// &
                'its nodes with _NODE or _SET')
          end if
        end if
        if (motion%vector_id > 0 .and. (abs(motion%dof) == 4 .or. abs(motion%dof) == 8)) then
          m = id_map_find(look%vectors, motion%vector_id)
          if (m == 0) then
            call input_error(where, 'vector '//itoa(motion%vector_id)//' (VID) is not '// &
                'defined (*DEFINE_VECTOR)')
          else
            motion%direction = model%vectors(m)%direction
          end if
        end if
      end associate
    end do
  end subroutine resolve_constraints

  !> Nodal, pressure and body loads: targets, segments, curves, the part set of the body loads.
  subroutine resolve_loads(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    integer :: k, i
    character(len=:), allocatable :: where
    do k = 1, model%n_nodal_loads
      associate (load => model%nodal_loads(k))
        where = where_is(load%src, trim(merge('*LOAD_NODE_SET  ', '*LOAD_NODE_POINT', &
                                              load%target_kind == ON_NODE_SET)))
        call resolve_target(look, load%target_kind, load%target_id, load%target, where)
        call resolve_curve(look, load%curve_id, load%curve, where, '')
        if (load%cid > 0) then                   ! the force along the system's axis DOF
          i = find_system(look, load%cid, where, 'CID: ')
          if (i > 0) load%direction = model%systems(i)%axes(:, load%dof)
        end if
      end associate
    end do
    do k = 1, model%n_pressure_loads
      associate (load => model%pressure_loads(k))
        if (load%set_id > 0) then
          where = where_is(load%src, '*LOAD_SEGMENT_SET')
          call resolve_target(look, ON_SEGMENT_SET, load%set_id, load%set, where)
        else
          where = where_is(load%src, '*LOAD_SEGMENT')
          do i = 1, 4
            load%nodes(i) = id_map_find(look%nodes, load%node_ids(i))
            if (load%nodes(i) == 0 .and. (i < 4 .or. load%node_ids(4) /= load%node_ids(3))) &
              call input_error(where, 'node '//itoa(load%node_ids(i))//' (N'//itoa(i)// &
                  ') is not defined')
          end do
        end if
        call resolve_curve(look, load%curve_id, load%curve, where, '')
      end associate
    end do
    do k = 1, model%n_body_loads
      associate (load => model%body_loads(k))
        where = where_is(load%src, '*LOAD_BODY_'//AXIS_NAMES(load%direction))
        call resolve_curve(look, load%curve_id, load%curve, where, 'LCID ')
      end associate
    end do
    if (model%body_part_set_id > 0) call resolve_target(look, ON_PART_SET, &
        model%body_part_set_id, model%body_part_set, &
        where_is(model%body_part_src, '*LOAD_BODY_PARTS'), 'PSID: ')
    if (model%body_part_set_id > 0 .and. model%n_body_loads == 0) call warn( &
        where_is(model%body_part_src, '*LOAD_BODY_PARTS')//': no *LOAD_BODY_X, _Y or _Z in '// &
        'the deck: it has no effect')
  end subroutine resolve_loads

  !> Initial velocities: targets and exempted node sets.
  subroutine resolve_initial_velocities(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    integer :: k, m
    character(len=:), allocatable :: where
    do k = 1, model%n_initial_velocities
      associate (iv => model%initial_velocities(k))
        if (iv%generation) then
          where = where_is(iv%src, '*INITIAL_VELOCITY_GENERATION')
        else if (iv%target_kind == ON_NODE) then
          where = where_is(iv%src, '*INITIAL_VELOCITY_NODE')
        else
          where = where_is(iv%src, '*INITIAL_VELOCITY')
        end if
        call resolve_target(look, iv%target_kind, iv%target_id, iv%target, where)
        if (iv%exempt_set_id > 0) call resolve_target(look, ON_NODE_SET, iv%exempt_set_id, &
            iv%exempt_set, where, 'NSIDEX: ')
        if (iv%box_id > 0) call resolve_box(look, iv%box_id, iv%box, where)
        if (iv%system_id > 0) then               ! ICID: the components into global ones
          m = find_system(look, iv%system_id, where, 'ICID: ')
          if (m > 0) then
            associate (axes => model%systems(m)%axes)
              iv%v = matmul(axes, iv%v)
              iv%omega_vector = matmul(axes, iv%omega_vector)
              iv%v_exempt = matmul(axes, iv%v_exempt)
              iv%axis = matmul(axes, iv%axis)
            end associate
            iv%system_id = 0
          end if
        end if
      end associate
    end do
  end subroutine resolve_initial_velocities

  !> Contact surfaces (by SURFATYP/SURFBTYP; a single-surface contact's SURFA only) and
  !> rigid-wall node sets.
  subroutine resolve_contacts(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    integer :: k, k2
    integer, allocatable :: parts(:)
    character(len=:), allocatable :: where, who
    ! tied contacts: both sides deformable (a node tied to a rigid part moves with it:
    ! *CONSTRAINED_EXTRA_NODES)
    do k = 1, model%n_ties
      associate (tie => model%ties(k))
        where = where_is(tie%src, trim(tie%keyword))
        who = 'contact: '
        if (tie%id /= 0) who = 'contact '//itoa(tie%id)//': '
        call resolve_target(look, surface_kind(tie%surf_a_type), tie%surf_a_id, tie%surf_a, &
                            where, who//'SURFA ')
        call resolve_target(look, surface_kind(tie%surf_b_type), tie%surf_b_id, tie%surf_b, &
                            where, who//'SURFB ')
        call surface_a_parts(tie, parts)
        if (any([(part_is_rigid(parts(k2)), k2 = 1, size(parts))])) call input_error(where, &
            who//'SURFA holds a *MAT_RIGID part: a tied contact joins deformable bodies (tie '// &
            'nodes to a rigid part with *CONSTRAINED_EXTRA_NODES)')
        if (tie%surf_b > 0 .and. any(tie%surf_b_type == [SURFACE_PART, SURFACE_PART_SET])) then
          if (any_rigid(surface_kind(tie%surf_b_type), tie%surf_b)) call input_error(where, &
              who//'SURFB holds a *MAT_RIGID part: a tied contact joins deformable bodies '// &
              '(tie nodes to a rigid part with *CONSTRAINED_EXTRA_NODES)')
        end if
        if (tie%companion > 0) then             ! a tiebreak's contact: the same surfaces
          model%contacts(tie%companion)%surf_a = tie%surf_a
          model%contacts(tie%companion)%surf_b = tie%surf_b
        end if
      end associate
    end do
    do k = 1, model%n_contacts
      associate (contact => model%contacts(k))
        if (contact%single_surface) then
          where = where_is(contact%src, '*CONTACT_AUTOMATIC_SINGLE_SURFACE')
        else
          where = where_is(contact%src, '*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE')
        end if
        who = 'contact: '
        if (contact%id /= 0) who = 'contact '//itoa(contact%id)//': '
        if (contact%companion == 0) then      ! (a tiebreak's: its tie's surfaces, above)
          if (contact%surf_a_type /= SURFACE_ALL_PARTS) call resolve_target(look, &
              surface_kind(contact%surf_a_type), contact%surf_a_id, contact%surf_a, where, &
              who//'SURFA ')
          if (.not. contact%single_surface) call resolve_target(look, &
              surface_kind(contact%surf_b_type), contact%surf_b_id, contact%surf_b, where, &
              who//'SURFB ')
        end if
        call surface_a_parts(contact, parts)
        if (contact%fs == FS_FROM_PARTS) call part_friction(contact, parts, where, who)
        ! the penalty comes from SURFA's elements: a SURFA of rigid parts only has none (a
        ! tiebreak's SURFA: reported for its tie)
        if (size(parts) > 0 .and. contact%companion == 0) then
          if (all([(part_is_rigid(parts(k2)), k2 = 1, size(parts))])) then
            if (contact%single_surface) then
              call input_error(where, who//'SURFA holds *MAT_RIGID parts only; mefem takes '// &
                  'the penalty from the deformable elements of the surface')
            else
              call input_error(where, who//'SURFA holds *MAT_RIGID parts only; mefem takes '// &
                  'the penalty from SURFA''s elements, so SURFA must be the deformable body '// &
                  '(swap SURFA and SURFB: the rigid tool is SURFB)')
            end if
          end if
        else if (contact%surf_a_type == SURFACE_ALL_BUT_SET .and. contact%surf_a > 0) then
          call input_error(where, who//'SURFATYP = 6: part set '//itoa(contact%surf_a_id)// &
              ' holds every part, so no part is left for the contact')
        end if
      end associate
    end do
    do k = 1, model%n_transducers
      associate (transducer => model%transducers(k))
        where = where_is(transducer%src, trim(transducer%keyword))
        who = 'contact: '
        if (transducer%id /= 0) who = 'contact '//itoa(transducer%id)//': '
        call resolve_target(look, surface_kind(transducer%surf_a_type), transducer%surf_a_id, &
                            transducer%surf_a, where, who//'SURFA ')
      end associate
    end do
    do k = 1, model%n_rigid_constraints
      associate (rc => model%rigid_constraints(k))
        if (rc%kind == RIGID_NODAL) then
          ! a body of its nodes: a node set (*CONSTRAINED_NODAL_RIGID_BODY) or two nodes
          ! (*CONSTRAINED_SPOTWELD)
          if (rc%target_kind == ON_NODE_SET) then
            where = where_is(rc%src, '*CONSTRAINED_NODAL_RIGID_BODY')
            call resolve_target(look, ON_NODE_SET, rc%target_id, rc%target, where, 'NSID: ')
          else
            where = where_is(rc%src, '*CONSTRAINED_SPOTWELD')
            call resolve_target(look, ON_NODE, rc%target_id, rc%target, where, 'N1: ')
            call resolve_target(look, ON_NODE, rc%second_id, rc%second, where, 'N2: ')
          end if
          cycle
        end if
        where = where_is(rc%src, trim(merge('*CONSTRAINED_RIGID_BODIES', &
                                            '*CONSTRAINED_EXTRA_NODES ', rc%kind == RIGID_MERGE)))
        call resolve_target(look, ON_PART, rc%lead_id, rc%lead, where, &
                            trim(merge('PIDL', 'PID ', rc%kind == RIGID_MERGE))//': ')
        if (rc%kind == RIGID_MERGE) then
          call resolve_target(look, rc%target_kind, rc%target_id, rc%target, where, 'PIDC: ')
        else
          call resolve_target(look, rc%target_kind, rc%target_id, rc%target, where)
        end if
        if (rc%lead > 0) call require_rigid(rc%lead, where)
        if (rc%kind == RIGID_MERGE .and. rc%target > 0) call require_rigid(rc%target, where)
      end associate
    end do
    do k = 1, model%n_added_masses
      associate (am => model%added_masses(k))
        where = where_is(am%src, trim(merge('*ELEMENT_MASS     ', '*ELEMENT_MASS_PART', &
                                            any(am%target_kind == [ON_NODE, ON_NODE_SET]))))
        call resolve_target(look, am%target_kind, am%target_id, am%target, where)
      end associate
    end do
    do k = 1, model%n_rigid_walls
      associate (wall => model%rigid_walls(k))
        where = where_is(wall%src, trim(wall%keyword))
        if (wall%node_set_id > 0) call resolve_target(look, ON_NODE_SET, wall%node_set_id, &
            wall%node_set, where)
        if (wall%motion_curve_id > 0) call resolve_curve(look, wall%motion_curve_id, &
            wall%motion_curve, where, 'LCID ')
        if (wall%exempt_set_id > 0) call resolve_target(look, ON_NODE_SET, &
            wall%exempt_set_id, wall%exempt_set, where, 'NSIDEX: ')
        if (wall%box_id > 0) call resolve_box(look, wall%box_id, wall%box, where)
      end associate
    end do

  contains

    !> The part must be a *MAT_RIGID part (the constraints act on rigid bodies; parts are not
    !> resolved yet: its material by id).
    subroutine require_rigid(p, where)
      integer, intent(in) :: p                    !< part index
      character(len=*), intent(in) :: where       !< for the message
      integer :: m
      m = id_map_find(look%materials, model%parts(p)%material_id)
      if (m <= 0) return
      if (model%materials(m)%kind /= MAT_RIGID) call input_error(where, 'part '// &
          itoa(model%parts(p)%id)//' is not a rigid part (*MAT_RIGID): the constraint '// &
          'joins rigid bodies and nodes to them')
    end subroutine require_rigid

    !> FS = -1: the friction FS, FD, DC of the *PART_CONTACT of SURFA's parts (a part, a
    !> part set, all parts or all but a set; all of them the same values).
    subroutine part_friction(contact, parts, where, who)
      type(contact_t), intent(inout) :: contact   !< the contact (SURFA resolved)
      integer, intent(in) :: parts(:)             !< SURFA's parts (surface_a_parts)
      character(len=*), intent(in) :: where, who !< for messages
      integer :: i
      if (contact%surf_a_type == SURFACE_SEGMENT_SET) then
        call input_error(where, who//'FS = -1 (friction of the SURFA parts'' *PART_CONTACT) '// &
            'needs SURFA as parts (SURFATYP 3, 2, 5 or 6)')
        return
      end if
      if (contact%surf_a_type == SURFACE_NODE_SET) then
        call input_error(where, who//'FS = -1 (friction of the SURFA parts'' *PART_CONTACT) '// &
            'needs SURFA as parts (SURFATYP 3, 2, 5 or 6), not a node set')
        return
      end if
      do i = 1, size(parts)
        associate (part => model%parts(parts(i)))
          if (.not. part%has_contact) then
            call input_error(where, who//'FS = -1 takes the friction of the SURFA parts'' '// &
                '*PART_CONTACT, but part '//itoa(part%id)//' has none (give it with '// &
                '*PART_CONTACT or set FS)')
            return
          end if
          if (i == 1) then
            contact%fs = part%contact_fs
            contact%fd = part%contact_fd
            contact%dc = part%contact_dc
          else if (part%contact_fs /= contact%fs .or. part%contact_fd /= contact%fd .or. &
                   part%contact_dc /= contact%dc) then
            call input_error(where, who//'FS = -1: the SURFA parts'' *PART_CONTACT '// &
                'frictions differ (part '//itoa(part%id)//'); mefem takes one friction per '// &
                'contact')
            return
          end if
        end associate
      end do
    end subroutine part_friction

    !> The part indices of a contact's SURFA (ascending; empty for a segment set or an
    !> unresolved target): a part, a part set's members, all parts (SURFATYP 5) or all parts
    !> but a part set's (6).
    subroutine surface_a_parts(contact, parts)
      type(contact_t), intent(in) :: contact      !< the contact (SURFA resolved)
      integer, allocatable, intent(out) :: parts(:) !< part indices
      logical :: keep(model%n_parts)
      integer :: p
      keep = .false.
      select case (contact%surf_a_type)
      case (SURFACE_PART)
        if (contact%surf_a > 0) keep(contact%surf_a) = .true.
      case (SURFACE_PART_SET, SURFACE_ALL_BUT_SET)
        if (contact%surf_a > 0) then
          associate (set => model%sets(contact%surf_a))
            if (allocated(set%members)) then
              if (all(set%members >= 1 .and. set%members <= model%n_parts)) &
                keep(set%members) = .true.
            end if
          end associate
          if (contact%surf_a_type == SURFACE_ALL_BUT_SET) keep = .not. keep
        end if
      case (SURFACE_ALL_PARTS)
        keep = .true.
      end select
      parts = pack([(p, p = 1, model%n_parts)], keep)
    end subroutine surface_a_parts

    !> Some part of a contact surface (a part, or a part set) is *MAT_RIGID.
    logical function any_rigid(kind, target)
      integer, intent(in) :: kind               !< ON_PART or ON_PART_SET
      integer, intent(in) :: target             !< part or set index
      integer :: i
      any_rigid = .false.
      if (kind == ON_PART) then
        any_rigid = part_is_rigid(target)
      else
        associate (set => model%sets(target))
          if (.not. allocated(set%members)) return
          do i = 1, size(set%members)
            if (set%members(i) >= 1 .and. set%members(i) <= model%n_parts) &
              any_rigid = any_rigid .or. part_is_rigid(set%members(i))
          end do
        end associate
      end if
    end function any_rigid

    !> Part p's material is *MAT_RIGID (false when it is not defined).
    logical function part_is_rigid(p)
      integer, intent(in) :: p                  !< part index
      integer :: m
      m = id_map_find(look%materials, model%parts(p)%material_id)
      part_is_rigid = .false.
      if (m > 0) part_is_rigid = model%materials(m)%kind == MAT_RIGID
    end function part_is_rigid

  end subroutine resolve_contacts

  !> ON_* kind of a contact surface type (0 segment set, 2 part set, 3 part, 4 node set, 6 all
  !> parts but a part set: the set).
  pure integer function surface_kind(surface_type)
    integer, intent(in) :: surface_type   !< SURFATYP or SURFBTYP
    select case (surface_type)
    case (2, 6)
      surface_kind = ON_PART_SET
    case (3)
      surface_kind = ON_PART
    case (4)
      surface_kind = ON_NODE_SET
    case default
      surface_kind = ON_SEGMENT_SET
    end select
  end function surface_kind

  !> History nodes and node sets of *DATABASE_HISTORY_NODE(_SET).
  subroutine resolve_outputs(model, look)
    type(model_t), intent(inout) :: model     !< the model
    type(lookup_t), intent(in) :: look        !< lookups
    integer :: k
    associate (c => model%controls)
      if (allocated(c%history_nodes)) deallocate(c%history_nodes)
      if (allocated(c%history_sets)) deallocate(c%history_sets)
      allocate(c%history_nodes(c%n_history_nodes), c%history_sets(c%n_history_sets))
      do k = 1, c%n_history_nodes
        call resolve_target(look, ON_NODE, c%history_node_ids(k), c%history_nodes(k), &
            where_is(c%history_node_src(k), '*DATABASE_HISTORY_NODE'))
      end do
      do k = 1, c%n_history_sets
        call resolve_target(look, ON_NODE_SET, c%history_set_ids(k), c%history_sets(k), &
            where_is(c%history_set_src(k), '*DATABASE_HISTORY_NODE_SET'))
      end do
    end associate
  end subroutine resolve_outputs

end module mefem_resolve_conditions
