!> Keyword handlers for deck-level and control keywords: *KEYWORD, *TITLE, *PARAMETER,
!> *CONTROL_* and *DATABASE_* output requests, and mefem's own *MEFEM_* keywords.
module mefem_read_controls
  use mefem_kinds, only: wp
  use mefem_strings, only: to_upper, itoa, rtoa
  use mefem_parameters, only: parameter_define, split_parameter_spec
  use mefem_expressions, only: evaluate_expression
  use mefem_numbers, only: parse_real, parse_int
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_int, get_text, &
                         card_error, card_warning, keyword_error
  use mefem_errors, only: warn
  use mefem_deck_source, only: location
  use mefem_model, only: model_t, source_t
  use mefem_card_layouts, only: read_layout_card, real_field, int_field, card_fields_t
  implicit none
  private

  public :: read_keyword_card, read_title, read_parameter, read_parameter_expression, &
            read_control_termination
  public :: read_control_timestep, read_control_solution, read_control_implicit_general, &
            read_control_implicit_solution, read_control_implicit_auto, &
            read_database_binary_d3plot, read_database_interval, read_database_history_node, &
            read_mefem_enrichment, read_control_hourglass
  public :: DATABASE_GLSTAT, DATABASE_RCFORC, DATABASE_NODOUT
  public :: read_database_restart, DATABASE_D3DUMP, DATABASE_RUNRSF

  ! ASCII output files of read_database_interval
  integer, parameter :: DATABASE_GLSTAT = 1, DATABASE_RCFORC = 2, DATABASE_NODOUT = 3
  integer, parameter :: DATABASE_D3DUMP = 1, DATABASE_RUNRSF = 2   !< restart files

  integer, parameter :: W_10(8) = 10   !< standard 8 x 10 card
  !> largest *MEFEM_ENRICHMENT BMASS accepted (bubble inertia 100 times the element's mass:
  !> far beyond any use; the default is 2.05 for tets, 1.43 for triangles)
  real(wp), parameter :: MAX_BUBBLE_MASS = 100.0_wp

  !> What a parameter's type and name must be (for the messages)
  character(len=*), parameter :: NAME_RULE = '(a type letter, then a name of up to 32 '// &
      'letters, digits and _ starting with a letter)'

contains

  !> *KEYWORD [memory] [LONG=Y|S|N] [I10=Y]: sets the deck's default field format.
  subroutine read_keyword_card(rd, line)
    type(reader_t), intent(inout) :: rd      !< reading state
    character(len=*), intent(in) :: line     !< keyword line without the '*'
    character(len=:), allocatable :: upper
    integer :: k
    type(card_t) :: card
    logical :: got
    upper = to_upper(line)
    k = index(upper, 'LONG=')
    if (k > 0 .and. k + 5 <= len(upper)) then
      select case (upper(k+5:k+5))
      case ('Y')
        rd%long_default = .true.
      case ('N', 'S')
        rd%long_default = .false.
      case default
        call keyword_error(rd, 'LONG= must be Y, S or N')
      end select
    end if
    if (index(upper, 'I10=Y') > 0) call keyword_error(rd, &
        'I10=Y (10-digit labels) is not supported; write the deck in LONG=Y format')
    do   ! *KEYWORD takes no cards; anything after it belongs to nobody
      call next_card(rd, card, got)
      if (.not. got) exit
      call card_error(card, 'unexpected data card after *KEYWORD')
    end do
  end subroutine read_keyword_card

  !> *TITLE: one card, the job title.
  subroutine read_title(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the title
    type(card_t) :: card
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (got) model%controls%title = card%text(1:min(card%length, 80))
  end subroutine read_title

  !> *PARAMETER: up to four (type+name, value) pairs per card, 10 columns each:
  !> 'R name' real, 'I name' integer, 'C name' character. The value is checked by type.
  subroutine read_parameter(rd)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(card_t) :: card
    logical :: got, ok
    integer :: pair, ivalue
    real(wp) :: rvalue
    character(len=:), allocatable :: spec, value, name
    character :: kind
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_10)
      do pair = 1, 4
        call get_text(card, 2*pair - 1, spec)
        call get_text(card, 2*pair, value)
        if (len(spec) == 0 .and. len(value) == 0) cycle
        ! the first character is the type (R, I, C), the other nine the name ('R tmax', 'Rtmax')
        call split_parameter_spec(spec, 'RIC', kind, name, ok)
        if (.not. ok) then
          call card_error(card, 'parameter '//itoa(pair)//': "'//spec// &
              '" is not "R name", "I name" or "C name" '//NAME_RULE)
          cycle
        end if
        ok = .true.
        if (kind == 'R') call parse_real(value, rvalue, ok)
        if (kind == 'I') call parse_int(value, ivalue, ok)
        if (.not. ok .or. (kind /= 'C' .and. len(value) == 0)) then
          call card_error(card, 'parameter '//name//': value "'//value// &
              '" is not a valid '//merge('real   ', 'integer', kind == 'R'))
          cycle
        end if
        call parameter_define(name, kind, value)
      end do
    end do
  end subroutine read_parameter

  !> *PARAMETER_EXPRESSION: repeated cards PRMR (columns 1-10: type letter R or I, then the
  !> name, as in *PARAMETER) and EXPRESSION (columns 11-80; mefem reads it to the end of the
  !> line). The expression is evaluated when the card is read (mefem_expressions) and defines
  !> the parameter; an I parameter takes the nearest integer (nint). A card with a comma
  !> outside parentheses is comma-separated: PRMR before the first comma, the expression after
  !> it (so 'R a,max(b,c)' and the fixed-column 'R a      max(b,c)' are both read).
  subroutine read_parameter_expression(rd)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(card_t) :: card
    logical :: got, ok_spec, ok_value
    integer :: first
    real(wp) :: value
    character(len=:), allocatable :: spec, name, text, message
    character :: kind
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      card%free = has_top_level_comma(card%text(1:card%length))
      call split_card(rd, card, [10, 70])
      if (card%unreadable) cycle
      call get_text(card, 1, spec)
      if (card%free) then
        first = card%last(1) + 2         ! after the first comma
      else
        first = card%first(2)
      end if
      text = ''
      if (first <= card%length) text = trim(adjustl(card%text(first:card%length)))
      call split_parameter_spec(spec, 'RIC', kind, name, ok_spec)
      if (.not. ok_spec) then
        if (len(text) == 0 .and. .not. card%free) then
          call card_error(card, '"'//spec//'" is not "R name" or "I name" '//NAME_RULE// &
              '; the expression starts in column 11 (or after a comma)')
          cycle
        end if
        call card_error(card, '"'//spec//'" is not "R name" or "I name" '//NAME_RULE)
        name = '"'//spec//'"'
      else if (kind == 'C') then
        call card_error(card, 'parameter '//name//': type C (text) cannot take an '// &
            'expression; write "R name" or "I name"')
        ok_spec = .false.
      end if
      if (len(text) == 0) then
        call card_error(card, 'parameter '//name//': the expression is empty')
        cycle
      end if
      call evaluate_expression(text, value, ok_value, message)
      if (.not. ok_value) then
        call card_error(card, 'parameter '//name//': expression "'//text//'": '//message)
        cycle
      end if
      if (.not. ok_spec) cycle
      if (kind == 'I') then
        if (value >= real(huge(1), wp) + 0.5_wp .or. value <= -real(huge(1), wp) - 1.5_wp) then
          call card_error(card, 'parameter '//name//': the value '//rtoa(value)//' of "'// &
              text//'" is outside the integer range')
          cycle
        end if
        call parameter_define(name, kind, itoa(nint(value)))
      else
        call parameter_define(name, kind, shortest_real_text(value))
      end if
    end do
  end subroutine read_parameter_expression

  !> True when s holds a comma outside parentheses (a comma-separated card).
  pure logical function has_top_level_comma(s)
    character(len=*), intent(in) :: s   !< the card text
    integer :: k, depth
    has_top_level_comma = .false.
    depth = 0
    do k = 1, len(s)
      select case (s(k:k))
      case ('(')
        depth = depth + 1
      case (')')
        depth = max(0, depth - 1)
      case (',')
        if (depth == 0) then
          has_top_level_comma = .true.
          return
        end if
      end select
    end do
  end function has_top_level_comma

  !> The shortest text (2 to 17 digits: "1.5E+000") that parse_real reads back as exactly x.
  function shortest_real_text(x) result(s)
    real(wp), intent(in) :: x   !< the value
    character(len=:), allocatable :: s
    character(len=40) :: buf
    character(len=16) :: fmt
    integer :: digits
    real(wp) :: back
    logical :: ok
    do digits = 2, 17
      write(fmt, '(a,i0,a,i0,a)') '(es', digits + 10, '.', digits - 1, 'e3)'
      write(buf, fmt) x
      s = trim(adjustl(buf))
      call parse_real(s, back, ok)
      if (ok .and. back == x) return
    end do
  end function shortest_real_text

  !> *CONTROL_TERMINATION: ENDTIM ENDCYC DTMIN ENDENG ENDMAS.
  subroutine read_control_termination(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (ENDTIM ENDCYC DTMIN ENDENG ENDMAS)')
      return
    end if
    call read_layout_card(rd, card, 'CONTROL_TERMINATION', 1, f)
    associate (c => model%controls)
      c%end_time = real_field(f, 'ENDTIM')
      c%end_cycle = int_field(f, 'ENDCYC')
      c%dt_min_fraction = real_field(f, 'DTMIN')
      c%end_energy = real_field(f, 'ENDENG')
      c%end_mass = real_field(f, 'ENDMAS')
      if (c%end_time < 0.0_wp) call card_error(card, 'field ENDTIM must not be negative')
      if (c%end_cycle < 0) call card_error(card, 'field ENDCYC must not be negative')
      if (c%end_time == 0.0_wp .and. c%end_cycle == 0) call card_error(card, &
          'field ENDTIM: the termination time must be positive (or give ENDCYC)')
      if (.not. card%bad .and. (c%end_energy /= 0.0_wp .or. (c%end_mass > 0.0_wp .and. &
          c%end_mass < 1.0e8_wp))) call card_warning(card, 'ENDENG and ENDMAS ignored: '// &
          'mefem has no energy or mass-change stop (ENDTIM, ENDCYC and DTMIN end the run)')
      c%have_termination = .true.
    end associate
  end subroutine read_control_termination

  !> *CONTROL_SOLUTION: SOLN NLQ ISNAN LCINT LCACC NCDCF NOCOP. LS-PrePost writes it into
  !> nearly every deck; SOLN 0 (structural) is what mefem computes, the thermal analyses
  !> (SOLN 1, 2) are an error. The other fields tune LS-DYNA's own implementation (vector
  !> length, NaN checks, curve discretisation: mefem evaluates curves exactly) and are read,
  !> not used.
  subroutine read_control_solution(rd)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    integer :: soln
    call next_card(rd, card, got, keep_blank=.true.)
    if (got) then
      call read_layout_card(rd, card, 'CONTROL_SOLUTION', 1, f)
      soln = int_field(f, 'SOLN')
      if (.not. card%bad .and. soln /= 0) call card_error(card, 'field SOLN = '//itoa(soln)// &
          ': mefem computes structural analyses only (SOLN 0); thermal (1) and coupled '// &
          'thermal-structural (2) analyses are not supported')
    end if
    call skip_remaining(rd)
  end subroutine read_control_solution

  !> *CONTROL_HOURGLASS: IHQ QH, the hourglass control of the one-point hexahedra of parts
  !> without a *HOURGLASS of their own (and of those whose *HOURGLASS leaves IHQ 0).
  subroutine read_control_hourglass(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (got) then
      call read_layout_card(rd, card, 'CONTROL_HOURGLASS', 1, f)
      model%controls%ihq = int_field(f, 'IHQ')
      model%controls%qh = real_field(f, 'QH')
      model%controls%hourglass_src = source_t(card%file, card%line)
      if (.not. card%bad) then
        if (model%controls%ihq < 0 .or. model%controls%ihq > 10) call card_error(card, &
            'field IHQ must be 0 to 10 (got '//itoa(model%controls%ihq)//')')
        if (model%controls%qh < 0.0_wp) call card_error(card, 'field QH must not be '// &
            'negative (got '//rtoa(model%controls%qh)//')')
      end if
    end if
    call skip_remaining(rd)
  end subroutine read_control_hourglass

  !> *CONTROL_TIMESTEP: DTINIT TSSFAC ISDO TSLIMT DT2MS LCTM ERODE MS1ST; the optional further
  !> cards (mass-scaling refinements) are accepted and not used. TSSFAC 0 means 0.9.
  subroutine read_control_timestep(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (DTINIT TSSFAC ISDO TSLIMT DT2MS LCTM ERODE MS1ST)')
      return
    end if
    call read_layout_card(rd, card, 'CONTROL_TIMESTEP', 1, f)
    associate (c => model%controls)
      c%dt_init = real_field(f, 'DTINIT')
      c%tssfac = real_field(f, 'TSSFAC')
      c%isdo = int_field(f, 'ISDO')
      c%tslimt = real_field(f, 'TSLIMT')
      c%dt2ms = real_field(f, 'DT2MS')
      c%lctm = int_field(f, 'LCTM')
      c%ms1st = int_field(f, 'MS1ST')
      c%lctm_src = source_t(card%file, card%line)
      if (.not. card%bad) then
        if (c%dt_init < 0.0_wp) call card_error(card, 'field DTINIT must not be negative '// &
            '(got '//rtoa(c%dt_init)//')')
        if (c%tssfac < 0.0_wp .or. c%tssfac > 1.0_wp) call card_error(card, 'field TSSFAC '// &
            'must be > 0 and <= 1 (a larger factor makes the explicit step unstable) (got '// &
            rtoa(c%tssfac)//')')
        if (c%isdo < 0 .or. c%isdo > 2) call card_error(card, 'field ISDO must be 0, 1 or '// &
            '2 (got '//itoa(c%isdo)//')')
        if (c%tslimt < 0.0_wp) call card_error(card, 'field TSLIMT must not be negative '// &
            '(got '//rtoa(c%tslimt)//')')
        if (c%lctm < 0) call card_error(card, 'field LCTM must not be negative (got '// &
            itoa(c%lctm)//')')
        if (c%ms1st /= 0 .and. c%ms1st /= 1) call card_error(card, 'field MS1ST must be 0 '// &
            'or 1 (got '//itoa(c%ms1st)//')')
        if (c%ms1st == 1 .and. c%dt2ms < 0.0_wp) call card_warning(card, 'MS1ST = 1 ignored: '// &
            'the added mass is recomputed every cycle (as MS1ST = 0)')
      end if
    end associate
    ! card 2 (DT2MSF DT2MSLC IMSCL ... RMSCL EMSCL IHDO): mass-scaling refinements mefem does
    ! not take; say so when they are set
    call next_card(rd, card, got, keep_blank=.true.)
    if (got) then
      block
        real(wp) :: dt2msf, rmscl
        integer :: dt2mslc, imscl
        call read_layout_card(rd, card, 'CONTROL_TIMESTEP', 2, f)
        dt2msf = real_field(f, 'DT2MSF')
        dt2mslc = int_field(f, 'DT2MSLC')
        imscl = int_field(f, 'IMSCL')
        rmscl = real_field(f, 'RMSCL')
        if (.not. card%bad .and. (dt2msf /= 0.0_wp .or. dt2mslc /= 0 .or. imscl /= 0 .or. &
                                  rmscl /= 0.0_wp)) &
          call card_warning(card, 'card 2 (DT2MSF, DT2MSLC, IMSCL, RMSCL) ignored: mass '// &
              'scaling is DT2MS of card 1 alone, on every part (doc/keywords.md)')
      end block
    end if
    call skip_remaining(rd)
  end subroutine read_control_timestep

  !> *CONTROL_IMPLICIT_GENERAL: IMFLAG DT0 IMFORM NSBS IGS CNSTN FORM ZERO_V.
  !> IMFLAG 0 explicit, 1 implicit; the switching and springback modes are not supported.
  subroutine read_control_implicit_general(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (IMFLAG DT0 IMFORM NSBS IGS CNSTN FORM ZERO_V)')
      return
    end if
    call read_layout_card(rd, card, 'CONTROL_IMPLICIT_GENERAL', 1, f)
    associate (c => model%controls)
      c%imflag = int_field(f, 'IMFLAG')
      c%dt0 = real_field(f, 'DT0')
      c%imform = int_field(f, 'IMFORM')
      c%nsbs = int_field(f, 'NSBS')
      c%igs = int_field(f, 'IGS')
      if (.not. card%bad) then
        if (c%imflag /= 0 .and. c%imflag /= 1) then
          call card_error(card, 'field IMFLAG = '//itoa(c%imflag)//' is not supported '// &
              '(0 explicit, 1 implicit)')
        else if (c%imflag == 1 .and. c%dt0 <= 0.0_wp) then
          call card_error(card, 'field DT0: the implicit analysis needs an initial time '// &
              'step DT0 > 0 (got '//rtoa(c%dt0)//')')
        end if
        if (c%nsbs < 1) call card_error(card, 'field NSBS must be >= 1 (got '// &
            itoa(c%nsbs)//')')
      end if
    end associate
    call skip_remaining(rd)
  end subroutine read_control_implicit_general

  !> *CONTROL_IMPLICIT_SOLUTION: NSOLVR ILIMIT MAXREF DCTOL ECTOL RCTOL LSTOL ABSTOL /
  !> DNORM DIVERG ISTIF NLPRINT NLNORM D3ITCTL CPCHK; further cards (arc length, line search
  !> details) are accepted and not used. Blank or 0 fields take LS-DYNA's defaults.
  subroutine read_control_implicit_solution(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (NSOLVR ILIMIT MAXREF DCTOL ECTOL RCTOL LSTOL '// &
          'ABSTOL)')
      return
    end if
    call read_layout_card(rd, card, 'CONTROL_IMPLICIT_SOLUTION', 1, f)
    associate (c => model%controls)
      c%nsolvr = int_field(f, 'NSOLVR')
      c%ilimit = int_field(f, 'ILIMIT')
      c%maxref = int_field(f, 'MAXREF')
      c%dctol = real_field(f, 'DCTOL')
      c%ectol = real_field(f, 'ECTOL')
      c%rctol = real_field(f, 'RCTOL')
      c%lstol = real_field(f, 'LSTOL')
      c%abstol = real_field(f, 'ABSTOL')
      if (.not. card%bad) then
        if (.not. any(c%nsolvr == [1, 2, 12])) call card_error(card, 'field NSOLVR = '// &
            itoa(c%nsolvr)//' is not supported (1 linear, 2 or 12 nonlinear with BFGS '// &
            'updates)')
        if (c%ilimit < 1) call card_error(card, 'field ILIMIT must be >= 1 (got '// &
            itoa(c%ilimit)//')')
        if (c%dctol < 0.0_wp .or. c%ectol < 0.0_wp .or. c%rctol < 0.0_wp .or. &
            c%lstol < 0.0_wp .or. c%abstol < 0.0_wp) call card_error(card, 'fields DCTOL '// &
            'ECTOL RCTOL LSTOL ABSTOL must be positive (negative values select curves or '// &
            'special modes, which are not supported)')
      end if
      call next_card(rd, card2, got, keep_blank=.true.)
      if (got) then
        call read_layout_card(rd, card2, 'CONTROL_IMPLICIT_SOLUTION', 2, f)
        c%dnorm = int_field(f, 'DNORM')
        c%diverg = int_field(f, 'DIVERG')
        c%istif = int_field(f, 'ISTIF')
        c%nlprint = int_field(f, 'NLPRINT')
        c%nlnorm = int_field(f, 'NLNORM')
        if (.not. card2%bad) then
          if (c%dnorm /= 1 .and. c%dnorm /= 2) call card_error(card2, 'field DNORM must '// &
              'be 1 or 2 (got '//itoa(c%dnorm)//')')
          if (c%diverg /= 1 .and. c%diverg /= 2) call card_error(card2, 'field DIVERG '// &
              'must be 1 or 2 (got '//itoa(c%diverg)//')')
          if (c%istif < 1) call card_error(card2, 'field ISTIF must be >= 1 (got '// &
              itoa(c%istif)//')')
        end if
      end if
    end associate
    call skip_remaining(rd)
  end subroutine read_control_implicit_solution

  !> *CONTROL_IMPLICIT_AUTO: IAUTO ITEOPT ITEWIN DTMIN DTMAX DTEXP KFAIL KCYCLE.
  subroutine read_control_implicit_auto(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (IAUTO ITEOPT ITEWIN DTMIN DTMAX DTEXP KFAIL '// &
          'KCYCLE)')
      return
    end if
    call read_layout_card(rd, card, 'CONTROL_IMPLICIT_AUTO', 1, f)
    associate (c => model%controls)
      c%iauto = int_field(f, 'IAUTO')
      c%iteopt = int_field(f, 'ITEOPT')
      c%itewin = int_field(f, 'ITEWIN')
      c%auto_dtmin = real_field(f, 'DTMIN')
      c%auto_dtmax = real_field(f, 'DTMAX')
      c%dtexp = real_field(f, 'DTEXP')
      c%kfail = int_field(f, 'KFAIL')
      if (.not. card%bad) then
        if (c%iauto < 0 .or. c%iauto > 2) call card_error(card, 'field IAUTO = '// &
            itoa(c%iauto)//' is not supported (0 fixed step, 1 or 2 automatic)')
        if (c%iteopt < 1 .or. c%itewin < 0) call card_error(card, 'fields ITEOPT >= 1 and '// &
            'ITEWIN >= 0 expected (got '//itoa(c%iteopt)//' and '//itoa(c%itewin)//')')
        if (c%auto_dtmin < 0.0_wp .or. c%auto_dtmax < 0.0_wp) call card_error(card, &
            'fields DTMIN/DTMAX must not be negative (a negative DTMAX selects a curve, '// &
            'which is not supported)')
        if (c%auto_dtmax > 0.0_wp .and. c%auto_dtmin > c%auto_dtmax) call card_error(card, &
            'field DTMIN ('//rtoa(c%auto_dtmin)//') is larger than DTMAX ('// &
            rtoa(c%auto_dtmax)//')')
      end if
    end associate
    call skip_remaining(rd)
  end subroutine read_control_implicit_auto

  !> *DATABASE_BINARY_D3PLOT: DT LCDT BEAM NPLTC PSETID / [IOOPT ...]: the interval of
  !> mefem's result states (VTK/HDF5). NPLTC > 0 overrides DT (= ENDTIM / NPLTC).
  subroutine read_database_binary_d3plot(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    integer :: lcdt, psetid
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (DT LCDT BEAM NPLTC PSETID)')
      return
    end if
    call read_layout_card(rd, card, 'DATABASE_BINARY_D3PLOT', 1, f)
    associate (c => model%controls)
      c%plot_interval = real_field(f, 'DT')
      c%plot_src = source_t(card%file, card%line)
      lcdt = int_field(f, 'LCDT')
      c%plot_count = int_field(f, 'NPLTC')
      psetid = int_field(f, 'PSETID')
      if (.not. card%bad) then
        if (c%plot_interval < 0.0_wp .or. c%plot_count < 0) then
          call card_error(card, 'fields DT and NPLTC must not be negative')
        else if (c%plot_interval == 0.0_wp .and. c%plot_count == 0) then
          call card_error(card, 'give the output interval DT > 0 or the number of states '// &
              'NPLTC > 0')
        end if
        if (lcdt /= 0) call warn(location(card%file, card%line)//': *DATABASE_BINARY_D3PLOT: '// &
            'LCDT (interval from a curve) ignored; DT or NPLTC is used')
        if (psetid /= 0) call warn(location(card%file, card%line)// &
            ': *DATABASE_BINARY_D3PLOT: PSETID ignored; all parts are written')
      end if
    end associate
    call skip_remaining(rd)
  end subroutine read_database_binary_d3plot

  !> *DATABASE_GLSTAT / *DATABASE_RCFORC / *DATABASE_NODOUT: DT BINARY LCUR IOOPT ...
  subroutine read_database_interval(rd, which, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    integer, intent(in) :: which             !< DATABASE_GLSTAT, _RCFORC or _NODOUT
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    real(wp) :: dt
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (DT BINARY LCUR IOOPT)')
      return
    end if
    call read_layout_card(rd, card, 'DATABASE_GLSTAT', 1, f)      ! (the three share it)
    dt = real_field(f, 'DT')
    if (.not. card%bad) then
      if (dt < 0.0_wp) then
        call card_error(card, 'field DT must not be negative (got '//rtoa(dt)//')')
      else
        select case (which)
        case (DATABASE_GLSTAT)
          model%controls%glstat_interval = dt
          model%controls%glstat_src = source_t(card%file, card%line)
        case (DATABASE_RCFORC)
          model%controls%rcforc_interval = dt
          model%controls%rcforc_src = source_t(card%file, card%line)
        case (DATABASE_NODOUT)
          model%controls%nodout_interval = dt
          model%controls%nodout_src = source_t(card%file, card%line)
        end select
      end if
    end if
    call skip_remaining(rd)
  end subroutine read_database_interval

  !> *DATABASE_BINARY_D3DUMP / *DATABASE_BINARY_RUNRSF: CYCL LCDT BEAM NPLTC PSETID CID NSKIP:
  !> a restart file every CYCL cycles (d3dump01, d3dump02, ... each kept; runrsf overwritten);
  !> D3DUMP's NPLTC > 0 also at every ENDTIM / NPLTC.
  subroutine read_database_restart(rd, which, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    integer, intent(in) :: which             !< DATABASE_D3DUMP or DATABASE_RUNRSF
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    real(wp) :: cycles
    integer :: npltc
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (CYCL LCDT BEAM NPLTC PSETID CID NSKIP)')
      return
    end if
    call read_layout_card(rd, card, 'DATABASE_BINARY_D3DUMP', 1, f)   ! (RUNRSF shares it)
    cycles = real_field(f, 'CYCL')
    npltc = int_field(f, 'NPLTC')
    if (.not. card%bad) then
      if (which == DATABASE_RUNRSF) npltc = 0          ! (NPLTC is D3DUMP's only)
      if (npltc < 0) then
        call card_error(card, 'field NPLTC (restart files over ENDTIM) must not be negative '// &
                        '(got '//itoa(npltc)//')')
      else if (cycles == 0.0_wp .and. npltc == 0) then
        if (which == DATABASE_D3DUMP) then
          call card_error(card, 'give CYCL, the cycles between restart files (or NPLTC, '// &
                          'their number over ENDTIM)')
        else
          call card_error(card, 'give CYCL, the cycles between restart files')
        end if
      else if (cycles /= 0.0_wp .and. (cycles < 1.0_wp .or. cycles /= aint(cycles) .or. &
                                       cycles > real(huge(1), wp))) then
        call card_error(card, 'field CYCL must be a whole number of cycles >= 1 (got '// &
                        rtoa(cycles)//')')
      else if (which == DATABASE_D3DUMP) then
        model%controls%d3dump_cycles = int(cycles)
        model%controls%d3dump_count = npltc
      else
        model%controls%runrsf_cycles = int(cycles)
      end if
    end if
    call skip_remaining(rd)
  end subroutine read_database_restart

  !> *DATABASE_HISTORY_NODE (node ids) / *DATABASE_HISTORY_NODE_SET (node-set ids):
  !> 8 x I10 per card, repeated; zeros and blanks ignored.
  subroutine read_database_history_node(rd, sets, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    logical, intent(in) :: sets              !< the ids are node-set ids
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    logical :: got
    integer :: i, id
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_10)
      do i = 1, 8
        call get_int(card, i, 'ID'//itoa(i), id)
        if (card%bad .or. id == 0) cycle
        if (id < 0) then
          call card_error(card, 'field ID'//itoa(i)//' must be a positive '// &
              trim(merge('node set', 'node    ', sets))//' id (got '//itoa(id)//')')
          cycle
        end if
        associate (c => model%controls)
          if (sets) then
            call append_id(c%history_set_ids, c%history_set_src, c%n_history_sets, id, card)
          else
            call append_id(c%history_node_ids, c%history_node_src, c%n_history_nodes, id, card)
          end if
        end associate
      end do
    end do
  end subroutine read_database_history_node

  !> Append an id and where it was given to growing lists.
  subroutine append_id(ids, src, n, id, card)
    integer, allocatable, intent(inout) :: ids(:)           !< ids
    type(source_t), allocatable, intent(inout) :: src(:)    !< their sources
    integer, intent(inout) :: n                             !< entries used
    integer, intent(in) :: id                               !< the new id
    type(card_t), intent(in) :: card                        !< its card
    integer, allocatable :: grown_ids(:)
    type(source_t), allocatable :: grown_src(:)
    if (.not. allocated(ids)) allocate(ids(16), src(16))
    if (n == size(ids)) then
      allocate(grown_ids(2*n), grown_src(2*n))
      grown_ids(1:n) = ids(1:n)
      grown_src(1:n) = src(1:n)
      call move_alloc(grown_ids, ids)
      call move_alloc(grown_src, src)
    end if
    n = n + 1
    ids(n) = id
    src(n) = source_t(card%file, card%line)
  end subroutine append_id

  !> *MEFEM_ENRICHMENT: SUPPORT BASIS BMASS. SUPPORT is the ratio a/L of the support radius of
  !> the meshfree (GMF) enrichment to the element size (default 1.5; > 1 so that the support
  !> reaches beyond the element, <= 3); BASIS 1 = atan GMF basis (default), 2 = exp; BMASS the
  !> explicit solver's inertia of the bubble dof over rho V (0 or blank: dim kappa^2).
  subroutine read_mefem_enrichment(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (SUPPORT BASIS)')
      return
    end if
    call read_layout_card(rd, card, 'MEFEM_ENRICHMENT', 1, f)
    associate (c => model%controls)
      c%support_radius = real_field(f, 'SUPPORT')
      c%gmf_basis = int_field(f, 'BASIS')
      c%bubble_mass = real_field(f, 'BMASS')
      if (.not. card%bad) then
        if (c%support_radius <= 1.0_wp .or. c%support_radius > 3.0_wp) call card_error(card, &
            'field SUPPORT (a/L) must be > 1.0 and <= 3.0: the support must reach beyond '// &
            'the element (got '//rtoa(c%support_radius)//')')
        if (c%gmf_basis /= 1 .and. c%gmf_basis /= 2) call card_error(card, 'field BASIS '// &
            'must be 1 (atan) or 2 (exp) (got '//itoa(c%gmf_basis)//')')
        if (c%bubble_mass < 0.0_wp .or. c%bubble_mass > MAX_BUBBLE_MASS) call card_error(card, &
            'field BMASS (bubble inertia / rho V) must be 0 (default) or in (0, '// &
            rtoa(MAX_BUBBLE_MASS)//'] (got '//rtoa(c%bubble_mass)//')')
      end if
    end associate
    call skip_remaining(rd)
  end subroutine read_mefem_enrichment

  !> Skip the further, optional cards of a control keyword (settings mefem does not use).
  subroutine skip_remaining(rd)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(card_t) :: card
    logical :: got
    do
      call next_card(rd, card, got)
      if (.not. got) exit
    end do
  end subroutine skip_remaining

end module mefem_read_controls
