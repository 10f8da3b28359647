!> Readers of the coordinate systems and vectors (*DEFINE_COORDINATE_SYSTEM, _VECTOR, _NODES,
!> *DEFINE_VECTOR): what they are read into (mefem_model's coordinate_system_t and vector_t);
!> their axes are computed when the model is resolved (mefem_resolve_conditions), where the
!> SPCs (CID), nodal loads (CID), initial velocities (ICID) and prescribed motions along a
!> vector (VID) use them. Card layouts as in the LS-DYNA keyword manual (doc/keywords.md 3.8).
module mefem_read_coordinates
  use mefem_kinds, only: wp
  use mefem_strings, only: itoa, to_upper
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_int, get_text, &
                         card_error, keyword_error
  use mefem_card_layouts, only: read_layout_card, real_field, int_field, card_fields_t
  use mefem_card_helpers, only: has_option, read_title_card
  use mefem_model, only: model_t, source_t, coordinate_system_t, vector_t, SYSTEM_BY_POINTS, &
                         SYSTEM_BY_VECTORS, SYSTEM_BY_NODES
  implicit none
  private

  public :: read_define_coordinate, read_define_vector

  integer, parameter :: W_10(8) = 10          !< standard 8 x 10 card (*DEFINE_COORDINATE_NODES)
  character(len=1), parameter :: AXIS(3) = ['X', 'Y', 'Z']

contains

  !> *DEFINE_COORDINATE_SYSTEM: CID XO YO ZO XL YL ZL CIDL / XP YP ZP (origin, a point on the
  !> local x axis, a point in the local x-y plane, given in system CIDL);
  !> *DEFINE_COORDINATE_VECTOR: CID XX YX ZX XV YV ZV NID (the x axis, a vector in the x-y
  !> plane; NID: the system turns with that node, which for solid nodes never turns);
  !> *DEFINE_COORDINATE_NODES: CID N1 N2 N3 FLAG DIR (N1 the origin, N2 on the axis DIR, X by
  !> default, N3 in the plane of that axis and the next (x-y, y-z, z-x), at their reference
  !> positions; FLAG 1: the system moves with the nodes, for the SPCs given in it). Each card
  !> (pair, _SYSTEM) defines a system; with _TITLE, one system after its title.
  subroutine read_define_coordinate(rd, kind, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    integer, intent(in) :: kind                  !< SYSTEM_BY_POINTS, _VECTORS or _NODES
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card, card2
    type(coordinate_system_t) :: system
    character(len=80) :: title
    character(len=:), allocatable :: direction
    logical :: got, bad
    type(card_fields_t) :: f
    integer :: k, nread, flag
    call read_title_card(rd, options, title)
    nread = 0
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      nread = nread + 1
      system = coordinate_system_t()
      system%kind = kind
      system%src = source_t(card%file, card%line)
      bad = .false.
      select case (kind)
      case (SYSTEM_BY_POINTS)
        call read_layout_card(rd, card, 'DEFINE_COORDINATE_SYSTEM', 1, f)
        system%id = int_field(f, 'CID')
        do k = 1, 3
          system%points(k, 1) = real_field(f, AXIS(k)//'O')
          system%points(k, 2) = real_field(f, AXIS(k)//'L')
        end do
        system%reference_id = int_field(f, 'CIDL')
        call next_card(rd, card2, got)
        if (.not. got) then
          call card_error(card, 'coordinate system '//itoa(system%id)//': missing card 2 '// &
                          '(XP YP ZP)')
          exit
        end if
        call read_layout_card(rd, card2, 'DEFINE_COORDINATE_SYSTEM', 2, f)
        do k = 1, 3
          system%points(k, 3) = real_field(f, AXIS(k)//'P')
        end do
        bad = card2%bad
        if (.not. bad .and. system%reference_id < 0) then
          call card_error(card, 'coordinate system '//itoa(system%id)//': field CIDL must '// &
                          'not be negative (got '//itoa(system%reference_id)//')')
          bad = .true.
        end if
      case (SYSTEM_BY_VECTORS)                   ! (NID read, not used: solid nodes do not turn)
        call read_layout_card(rd, card, 'DEFINE_COORDINATE_VECTOR', 1, f)
        system%id = int_field(f, 'CID')
        do k = 1, 3
          system%points(k, 1) = real_field(f, AXIS(k)//'X')
          system%points(k, 2) = real_field(f, AXIS(k)//'V')
        end do
      case (SYSTEM_BY_NODES)                     ! (DIR is text: not a card of the layout table)
        call split_card(rd, card, W_10)
        call get_int(card, 1, 'CID', system%id, required=.true.)
        do k = 1, 3
          call get_int(card, 1 + k, 'N'//itoa(k), system%node_ids(k), required=.true.)
        end do
        call get_int(card, 5, 'FLAG', flag)
        call get_text(card, 6, direction)
        if (.not. card%bad) then
          system%moving = flag == 1
          if (flag /= 0 .and. flag /= 1) then
            call card_error(card, 'coordinate system '//itoa(system%id)//': field FLAG must '// &
                'be 0 (the system of the nodes'' reference positions) or 1 (it moves with '// &
                'them) (got '//itoa(flag)//')')
            bad = .true.
          else if (len_trim(direction) > 0) then
            system%first_axis = index('XYZ', to_upper(trim(adjustl(direction))))
            if (len_trim(adjustl(direction)) /= 1 .or. system%first_axis == 0) then
              call card_error(card, 'coordinate system '//itoa(system%id)//': DIR = '// &
                  trim(adjustl(direction))//' is not an axis: X (the default), Y or Z, the '// &
                  'axis from N1 to N2')
              bad = .true.
            end if
          end if
        end if
      end select
      if (card%bad .or. bad) cycle
      if (system%id <= 0) then
        call card_error(card, 'field CID: coordinate system id must be positive (got '// &
                        itoa(system%id)//')')
        cycle
      end if
      call add_system(model, system)
      if (has_option(options, 'TITLE')) exit
    end do
    if (nread == 0) call keyword_error(rd, 'missing card 1 (CID and the system''s definition)')
  end subroutine read_define_coordinate

  !> *DEFINE_VECTOR: VID XT YT ZT XH YH ZH CID, one vector per card (from tail to head, in
  !> system CID; 0 global); with _TITLE, one vector after its title.
  subroutine read_define_vector(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(vector_t) :: vector
    type(vector_t), allocatable :: grown(:)
    character(len=80) :: title
    logical :: got, by_nodes
    integer :: k, nread
    by_nodes = has_option(options, 'NODES')
    call read_title_card(rd, options, title)
    nread = 0
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      nread = nread + 1
      vector = vector_t()
      if (by_nodes) then
        call read_layout_card(rd, card, 'DEFINE_VECTOR_NODES', 1, f)
        vector%id = int_field(f, 'VID')
        vector%tail_node = int_field(f, 'NODET')
        vector%head_node = int_field(f, 'NODEH')
      else
        call read_layout_card(rd, card, 'DEFINE_VECTOR', 1, f)
        vector%id = int_field(f, 'VID')
        do k = 1, 3
          vector%tail(k) = real_field(f, AXIS(k)//'T')
          vector%head(k) = real_field(f, AXIS(k)//'H')
        end do
        vector%system_id = int_field(f, 'CID')
      end if
      vector%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (vector%id <= 0) then
        call card_error(card, 'field VID: vector id must be positive (got '// &
                        itoa(vector%id)//')')
        cycle
      else if (by_nodes .and. (vector%tail_node <= 0 .or. vector%head_node <= 0 .or. &
                               vector%tail_node == vector%head_node)) then
        call card_error(card, 'vector '//itoa(vector%id)//': fields NODET and NODEH must be '// &
                        'two different node ids (got '//itoa(vector%tail_node)//', '// &
                        itoa(vector%head_node)//')')
        cycle
      else if (vector%system_id < 0) then
        call card_error(card, 'vector '//itoa(vector%id)//': field CID must not be '// &
                        'negative (got '//itoa(vector%system_id)//')')
        cycle
      end if
      if (.not. allocated(model%vectors)) allocate(model%vectors(0))
      if (model%n_vectors == size(model%vectors)) then
        allocate(grown(max(8, 2*model%n_vectors)))
        grown(1:model%n_vectors) = model%vectors(1:model%n_vectors)
        call move_alloc(grown, model%vectors)
      end if
      model%n_vectors = model%n_vectors + 1
      model%vectors(model%n_vectors) = vector
      if (has_option(options, 'TITLE')) exit
    end do
    if (nread == 0 .and. by_nodes) then
      call keyword_error(rd, 'missing card 1 (VID NODET NODEH)')
    else if (nread == 0) then
      call keyword_error(rd, 'missing card 1 (VID XT YT ZT XH YH ZH CID)')
    end if
  end subroutine read_define_vector

  !> Append a coordinate system.
  subroutine add_system(model, item)
    type(model_t), intent(inout) :: model               !< model appended to
    type(coordinate_system_t), intent(in) :: item       !< the system
    type(coordinate_system_t), allocatable :: grown(:)
    if (.not. allocated(model%systems)) allocate(model%systems(0))
    if (model%n_systems == size(model%systems)) then
      allocate(grown(max(8, 2*model%n_systems)))
      grown(1:model%n_systems) = model%systems(1:model%n_systems)
      call move_alloc(grown, model%systems)
    end if
    model%n_systems = model%n_systems + 1
    model%systems(model%n_systems) = item
  end subroutine add_system

end module mefem_read_coordinates
