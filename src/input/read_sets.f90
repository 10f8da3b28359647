!> Keyword handlers for sets: *SET_NODE_LIST (*SET_NODE), *SET_NODE_LIST_GENERATE,
!> *SET_PART_LIST (*SET_PART) and *SET_SEGMENT, each with the _TITLE option.
!>
!> Card 1 is SID DA1-DA4 SOLVER (its layout in mefem_card_layouts: SET_NODE, for every set);
!> member cards follow until the next keyword (8 x I10 ids, zeros and blanks ignored;
!> GENERATE: ranges B1 E1 B2 E2 ...; segments: N1 N2 N3 N4 A1-A4).
!> Members are stored as user ids and resolved by resolve_conditions.
module mefem_read_sets
  use mefem_strings, only: itoa, to_upper
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_int, get_text, &
                         card_error, keyword_error
  use mefem_card_helpers, only: has_option, read_title_card
  use mefem_card_layouts, only: read_layout_card, int_field, card_fields_t
  use mefem_model, only: model_t, set_t, source_t, SET_NODE, SET_PART, SET_SEGMENT, SET_SOLID, &
                         SET_SHELL, &
                         GENERAL_ALL, GENERAL_NODE, GENERAL_PART, GENERAL_SET, GENERAL_BOX, GENERAL_SEG
  implicit none
  private

  public :: read_set_node, read_set_part, read_set_segment, set_keyword, read_set_element

  integer, parameter :: W_10(8) = 10                       !< standard 8 x 10 card

contains

  !> Keyword name of a set kind, for messages.
  function set_keyword(kind) result(s)
    integer, intent(in) :: kind   !< SET_* code
    character(len=:), allocatable :: s
    select case (kind)
    case (SET_NODE)
      s = '*SET_NODE_LIST'
    case (SET_PART)
      s = '*SET_PART_LIST'
    case (SET_SOLID)
      s = '*SET_SOLID'
    case (SET_SHELL)
      s = '*SET_SHELL'
    case default
      s = '*SET_SEGMENT'
    end select
  end function set_keyword

  !> *SET_SOLID and *SET_SHELL (_LIST)(_GENERATE)(_TITLE): element sets (solids and shells
  !> have separate id spaces). They are read and checked (every id defined; a range names at
  !> least one element); mefem computes nothing that takes an element set (the keywords that
  !> do are output requests, skipped), so a set changes no result.
  subroutine read_set_element(rd, options, kind, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    integer, intent(in) :: kind                  !< SET_SOLID or SET_SHELL
    type(model_t), intent(inout) :: model        !< model appended to
    type(set_t) :: set
    set%kind = kind
    call read_set(rd, options, model, set, trim(merge('solid', 'shell', kind == SET_SOLID)), &
                  generate=has_option(options, 'GENERATE'))
  end subroutine read_set_element

  !> *SET_NODE(_LIST)(_GENERATE)(_TITLE).
  subroutine read_set_node(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(set_t) :: set
    set%kind = SET_NODE
    if (has_option(options, 'GENERAL')) then
      call read_set_general(rd, options, model, set)
    else if (has_option(options, 'GENERATE')) then
      call read_set(rd, options, model, set, 'node', generate=.true.)
    else
      call read_set(rd, options, model, set, 'node', generate=.false.)
    end if
  end subroutine read_set_node

  !> *SET_NODE_GENERAL and *SET_PART_GENERAL (_TITLE): card 1 SID DA1-DA4 SOLVER, then entries
  !> OPTION E1 .. E7 (A10, 7 x I10) taken in order: ALL (every node / part), NODE (the nodes
  !> E1..E7; node sets only), PART (parts E1..E7; for a node set their elements' nodes), SET
  !> (the members of sets E1..E7 of the same kind), BOX (the nodes inside the boxes E1..E7 of
  !> *DEFINE_BOX; node sets only), and DNODE, DPART, DSET, DBOX, which remove those.
  !> Resolved by resolve_conditions (the members in ascending order).
  subroutine read_set_general(rd, options, model, set)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(set_t), intent(inout) :: set            !< the set (kind given)
    integer, parameter :: N_OPTIONS = 11
    character(len=5), parameter :: OPTION_NAME(N_OPTIONS) = [character(len=5) :: 'ALL', &
        'NODE', 'PART', 'SET', 'BOX', 'SEG', 'DNODE', 'DPART', 'DSET', 'DBOX', 'DSEG']
    integer, parameter :: OPTION_CODE(N_OPTIONS) = [GENERAL_ALL, GENERAL_NODE, GENERAL_PART, &
        GENERAL_SET, GENERAL_BOX, GENERAL_SEG, -GENERAL_NODE, -GENERAL_PART, -GENERAL_SET, &
        -GENERAL_BOX, -GENERAL_SEG]
    !> the options each kind takes: node sets, part sets, segment sets
    logical, parameter :: NODE_TAKES(6) = [.true., .true., .true., .true., .true., .false.]
    logical, parameter :: PART_TAKES(6) = [.true., .false., .true., .true., .false., .false.]
    logical, parameter :: SEGMENT_TAKES(6) = [.true., .false., .true., .false., .true., .true.]
    type(card_t) :: card
    logical :: got, bad
    character(len=:), allocatable :: option, what, keyword, accepted
    integer :: i, k, ids(7), n_ids
    if (set%kind == SET_PART) then
      what = 'part set '
      keyword = '*SET_PART_GENERAL'
      accepted = '(ALL, PART, SET, DPART, DSET)'
    else if (set%kind == SET_SEGMENT) then
      what = 'segment set '
      keyword = '*SET_SEGMENT_GENERAL'
      accepted = '(ALL, PART, BOX, SEG, DPART, DBOX, DSEG)'
    else
      what = 'node set '
      keyword = '*SET_NODE_GENERAL'
      accepted = '(ALL, NODE, PART, SET, BOX, DNODE, DPART, DSET, DBOX)'
    end if
    if (.not. read_header(rd, options, set)) then
      call skip_members(rd)
      return
    end if
    bad = .false.
    set%general = .true.
    allocate(set%member_ids(64))
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_10)
      call get_text(card, 1, option)
      option = to_upper(trim(adjustl(option)))
      k = 0
      do i = 1, N_OPTIONS
        if (trim(OPTION_NAME(i)) == option) k = i
      end do
      if (k > 0) then                             ! an option of another kind of set
        select case (set%kind)
        case (SET_PART)
          if (.not. PART_TAKES(abs(OPTION_CODE(k)))) k = 0
        case (SET_SEGMENT)
          if (.not. SEGMENT_TAKES(abs(OPTION_CODE(k)))) k = 0
        case default
          if (.not. NODE_TAKES(abs(OPTION_CODE(k)))) k = 0
        end select
      end if
      if (k == 0) then
        call card_error(card, what//itoa(set%id)//': option "'//option//'" of '// &
            keyword//' is not supported '//accepted)
        bad = .true.
        cycle
      end if
      n_ids = 0
      do i = 1, 7
        call get_int(card, i + 1, 'E'//itoa(i), ids(n_ids + 1))
        if (ids(n_ids + 1) < 0) then
          call card_error(card, what//itoa(set%id)//': field E'//itoa(i)// &
                          ' must be a positive id (got '//itoa(ids(n_ids + 1))//')')
          bad = .true.
        else if (ids(n_ids + 1) > 0) then
          n_ids = n_ids + 1
        end if
      end do
      if (card%bad) bad = .true.
      if (OPTION_CODE(k) /= GENERAL_ALL .and. n_ids == 0 .and. .not. card%bad) then
        call card_error(card, what//itoa(set%id)//': option '//option// &
                        ' names no ids (E1 .. E7)')
        bad = .true.
      else if (abs(OPTION_CODE(k)) == GENERAL_SEG .and. .not. card%bad) then
        ! a segment: N1 N2 N3 (triangle, or E4 = E3) or N1 .. N4, in E1 .. E4
        if (n_ids < 3 .or. n_ids > 4) then
          call card_error(card, what//itoa(set%id)//': option '//option//' takes one '// &
              'segment, its nodes N1 N2 N3 (N4) in E1 .. E4')
          bad = .true.
        else if (n_ids == 3) then
          n_ids = 4
          ids(4) = ids(3)
        end if
      end if
      call ensure_room(set%member_ids, set%n + 2 + n_ids)
      set%member_ids(set%n + 1:set%n + 2 + n_ids) = [OPTION_CODE(k), n_ids, ids(1:n_ids)]
      set%n = set%n + 2 + n_ids
    end do
    if (set%n == 0 .and. .not. bad) then
      call keyword_error(rd, what//itoa(set%id)//': no entries (OPTION E1 .. E7)')
      bad = .true.
    end if
    if (bad) return
    call finish_set(rd, model, set, trim(what(1:4)))
  end subroutine read_set_general

  !> *SET_PART(_LIST)(_GENERAL)(_TITLE).
  subroutine read_set_part(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(set_t) :: set
    set%kind = SET_PART
    if (has_option(options, 'GENERAL')) then
      call read_set_general(rd, options, model, set)
    else
      call read_set(rd, options, model, set, 'part', generate=.false.)
    end if
  end subroutine read_set_part

  !> *SET_SEGMENT(_TITLE): N1 N2 N3 N4 per card (triangle: N4 = N3 or blank).
  subroutine read_set_segment(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(set_t) :: set
    type(card_t) :: card
    logical :: got, bad
    integer :: nodes(4), i
    set%kind = SET_SEGMENT
    if (has_option(options, 'GENERAL')) then
      call read_set_general(rd, options, model, set)
      return
    end if
    if (.not. read_header(rd, options, set)) then
      call skip_members(rd)
      return
    end if
    bad = .false.
    allocate(set%member_ids(64))
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_10)
      do i = 1, 4
        call get_int(card, i, 'N'//itoa(i), nodes(i))
      end do
      if (card%bad) then
        bad = .true.
        cycle
      end if
      ! 2D line segment: N1 N2 with N3 (and N4) blank or repeating N2 -> stored N1 N2 N2 N2
      if (nodes(3) == 0 .or. nodes(3) == nodes(2)) then
        if (all(nodes(3:4) == 0 .or. nodes(3:4) == nodes(2))) nodes(3:4) = nodes(2)
      end if
      if (nodes(4) == 0) nodes(4) = nodes(3)
      if (any(nodes(1:3) <= 0) .or. nodes(4) < 0) then
        call card_error(card, 'segment set '//itoa(set%id)//': a segment needs positive '// &
            'node ids N1 N2 (2D line) or N1 N2 N3 (and N4, or N4 = N3 for a triangle)')
        bad = .true.
        cycle
      end if
      if (nodes(1) == nodes(2) .or. (nodes(2) /= nodes(3) .and. (nodes(1) == nodes(3) .or. &
          nodes(4) == nodes(1) .or. nodes(4) == nodes(2)))) then
        call card_error(card, 'segment set '//itoa(set%id)//': segment '//itoa(nodes(1))// &
            ' '//itoa(nodes(2))//' '//itoa(nodes(3))//' '//itoa(nodes(4))// &
            ' repeats a node (only N4 = N3 is allowed, for a triangle)')
        bad = .true.
        cycle
      end if
      call ensure_room(set%member_ids, 4*set%n + 4)
      set%member_ids(4*set%n+1:4*set%n+4) = nodes
      set%n = set%n + 1
    end do
    if (bad) return
    call finish_set(rd, model, set, 'segment')
  end subroutine read_set_segment

  !> Common reader of node and part sets: a header and cards of 8 ids or of ranges.
  subroutine read_set(rd, options, model, set, what, generate)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(set_t), intent(inout) :: set            !< the set (kind given)
    character(len=*), intent(in) :: what         !< 'node', 'part', 'solid' or 'shell'
    logical, intent(in) :: generate              !< cards hold ranges B1 E1 B2 E2 ...
    type(card_t) :: card
    logical :: got, bad
    integer :: i, ids(8), first_id, last_id
    if (.not. read_header(rd, options, set)) then
      call skip_members(rd)
      return
    end if
    bad = .false.
    set%generated = generate
    allocate(set%member_ids(64))
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_10)
      do i = 1, 8
        if (generate) then
          call get_int(card, i, merge('B', 'E', mod(i, 2) == 1)//itoa((i + 1)/2), ids(i))
        else
          call get_int(card, i, id_field(what)//itoa(i), ids(i))
        end if
      end do
      if (card%bad) then
        bad = .true.
        cycle
      end if
      if (generate) then
        do i = 1, 4
          first_id = ids(2*i - 1)
          last_id = ids(2*i)
          if (first_id == 0 .and. last_id == 0) cycle
          if (first_id <= 0 .or. last_id < first_id) then
            call card_error(card, what//' set '//itoa(set%id)//': range B'//itoa(i)//' E'// &
                itoa(i)//' = '//itoa(first_id)//' '//itoa(last_id)//' is not a range of '// &
                'positive ids with E >= B')
            bad = .true.
            cycle
          end if
          ! the range itself (B, E): resolve_sets takes the defined nodes in it, so memory
          ! follows the nodes, not the width of the ranges
          call ensure_room(set%member_ids, 2*(set%n + 1))
          set%n = set%n + 1
          set%member_ids(2*set%n - 1:2*set%n) = [first_id, last_id]
        end do
      else
        do i = 1, 8
          if (ids(i) == 0) cycle
          if (ids(i) < 0) then
            call card_error(card, what//' set '//itoa(set%id)//': field '// &
                id_field(what)//itoa(i)// &
                ' must be a positive id (got '//itoa(ids(i))//')')
            bad = .true.
            cycle
          end if
          call ensure_room(set%member_ids, set%n + 1)
          set%n = set%n + 1
          set%member_ids(set%n) = ids(i)
        end do
      end if
    end do
    if (bad) return
    call finish_set(rd, model, set, what)
  end subroutine read_set

  !> Name of the id fields of a set's cards: NID (node), PID (part), EID (elements).
  function id_field(what) result(name)
    character(len=*), intent(in) :: what         !< 'node', 'part', 'solid' or 'shell'
    character(len=3) :: name
    select case (what)
    case ('node')
      name = 'NID'
    case ('part')
      name = 'PID'
    case default
      name = 'EID'
    end select
  end function id_field

  !> Title (when _TITLE) and card 1 SID DA1-DA4 SOLVER; false when the set cannot be read.
  logical function read_header(rd, options, set)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(set_t), intent(inout) :: set            !< the set
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    character(len=:), allocatable :: solver
    read_header = .false.
    call read_title_card(rd, options, set%title)
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (SID DA1 DA2 DA3 DA4 SOLVER)')
      return
    end if
    call read_layout_card(rd, card, 'SET_NODE', 1, f, text_after=[10])   ! (DA1-DA4 not used)
    set%id = int_field(f, 'SID')
    call get_text(card, card%nfields, solver)                          ! SOLVER
    set%src = source_t(card%file, card%line)
    if (card%bad) return
    if (set%id <= 0) then
      call card_error(card, 'field SID: set id must be positive (got '//itoa(set%id)//')')
      return
    end if
    if (len(solver) > 0 .and. solver /= 'MECH') then
      call card_error(card, 'set '//itoa(set%id)//': field SOLVER = "'//solver// &
          '" is not supported (only MECH, the default)')
      return
    end if
    read_header = .true.
  end function read_header

  !> Skip the member cards of a set whose header was bad.
  subroutine skip_members(rd)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(card_t) :: card
    logical :: got
    do
      call next_card(rd, card, got)
      if (.not. got) exit
    end do
  end subroutine skip_members

  !> An empty set is an error (it is only ever defined to be referenced); else append.
  subroutine finish_set(rd, model, set, what)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model appended to
    type(set_t), intent(inout) :: set            !< the set
    character(len=*), intent(in) :: what         !< 'node', 'part' or 'segment'
    integer, allocatable :: exact(:)
    if (set%n == 0) then
      call keyword_error(rd, what//' set '//itoa(set%id)//' has no members')
      return
    end if
    if (set%general) then
      exact = set%member_ids(1:set%n)              ! the entries (resolve_conditions)
    else if (set%kind == SET_SEGMENT) then
      exact = set%member_ids(1:4*set%n)
    else if (set%generated) then
      exact = set%member_ids(1:2*set%n)            ! ranges B E (resolve_sets)
    else
      exact = set%member_ids(1:set%n)
    end if
    call move_alloc(exact, set%member_ids)
    call add_set(model, set)
  end subroutine finish_set

  !> Make an id list hold at least n entries (capacity doubles).
  subroutine ensure_room(list, n)
    integer, allocatable, intent(inout) :: list(:)   !< the list
    integer, intent(in) :: n                         !< entries needed
    integer, allocatable :: grown(:)
    if (size(list) >= n) return
    allocate(grown(max(n, 2*size(list))))
    grown(1:size(list)) = list
    call move_alloc(grown, list)
  end subroutine ensure_room

  !> Append a set.
  subroutine add_set(model, set)
    type(model_t), intent(inout) :: model      !< model appended to
    type(set_t), intent(in) :: set             !< the set
    type(set_t), allocatable :: grown(:)
    if (.not. allocated(model%sets)) allocate(model%sets(0))
    if (model%n_sets == size(model%sets)) then
      allocate(grown(max(8, 2*model%n_sets)))
      grown(1:model%n_sets) = model%sets(1:model%n_sets)
      call move_alloc(grown, model%sets)
    end if
    model%n_sets = model%n_sets + 1
    model%sets(model%n_sets) = set
  end subroutine add_set

end module mefem_read_sets
