!> Arithmetic expressions of *PARAMETER_EXPRESSION, evaluated when read.
!>
!> A recursive-descent parser that evaluates while it parses. The syntax is Fortran's:
!>   expression := term { ('+' | '-') term }
!>   term       := unary { ('*' | '/') unary }
!>   unary      := ('+' | '-') unary | power
!>   power      := primary [ ('**' | '^') unary ]        (right-associative: 2**3**2 = 512)
!>   primary    := number | name | '&' name | name '(' expression { ',' expression } ')'
!>                 | '(' expression ')'
!> so ** binds tighter than unary minus (-2**2 = -4) and unary minus tighter than * and /.
!> Names are deck parameters (case-insensitive, with or without a leading '&'; a number
!> inside the expression is not read with the compact exponent of 1.4: 8.9-3 is 5.9) or the
!> constant pi; the functions are those of FUNCTION_NAMES. Every operation is checked before
!> it is made (division by zero, the domain of sqrt, log, asin ..., overflow), so that no
!> floating-point exception is raised (the debug build traps them) and the first problem is
!> reported with its column in the expression.
module mefem_expressions
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mefem_kinds, only: wp
  use mefem_strings, only: to_upper, to_lower, itoa, rtoa
  use mefem_numbers, only: parse_real
  use mefem_parameters, only: parameter_lookup
  implicit none
  private

  public :: evaluate_expression

  real(wp), parameter :: PI = 3.14159265358979323846264338327950288_wp
  !> log(huge), less a margin for the rounding of the logarithms the overflow tests compare
  real(wp), parameter :: LOG_HUGE = 709.782712893383973_wp - 1.0e-9_wp
  real(wp), parameter :: LOG_TWO = 0.693147180559945309417232121458176568_wp

  integer, parameter :: N_FUNCTIONS = 23
  character(len=5), parameter :: FUNCTION_NAMES(N_FUNCTIONS) = [character(len=5) :: &
    'ABS', 'SQRT', 'EXP', 'LOG', 'LOG10', 'SIN', 'COS', 'TAN', 'ASIN', 'ACOS', 'ATAN', &
    'ATAN2', 'SINH', 'COSH', 'TANH', 'MIN', 'MAX', 'MOD', 'SIGN', 'INT', 'NINT', 'AINT', &
    'ANINT']

  !> The parsing state: the text, the next column, and the first problem met.
  type :: parser_t
    character(len=:), allocatable :: text      !< the expression
    integer :: pos = 1                         !< column of the next character to read
    logical :: ok = .true.                     !< no problem met so far
    character(len=:), allocatable :: message   !< the first problem ('' while ok)
  end type parser_t

contains

  !> Evaluate an expression. ok is false when it cannot be evaluated; message then says why
  !> and where ('unexpected ')' at column 8 of the expression'), else it is ''.
  subroutine evaluate_expression(text, value, ok, message)
    character(len=*), intent(in) :: text                   !< the expression
    real(wp), intent(out) :: value                         !< its value (0 when not ok)
    logical, intent(out) :: ok                             !< it was evaluated
    character(len=:), allocatable, intent(out) :: message  !< the problem, or ''
    type(parser_t) :: p
    p%text = text
    p%message = ''
    value = 0.0_wp
    call skip_blanks(p)
    if (p%pos > len(p%text)) then
      call fail(p, 'the expression is empty')
    else
      value = parse_sum(p)
      call skip_blanks(p)
      if (p%ok .and. p%pos <= len(p%text)) then
        if (p%text(p%pos:p%pos) == ')') then
          call fail(p, 'unexpected '')'' at column '//itoa(p%pos)//' of the expression '// &
              '(no ''('' is open)')
        else
          call fail(p, 'unexpected '''//p%text(p%pos:p%pos)//''' at column '//itoa(p%pos)// &
              ' of the expression (an operator or the end was expected)')
        end if
      end if
      if (p%ok .and. .not. ieee_is_finite(value)) call fail(p, 'the result is not finite')
    end if
    ok = p%ok
    if (.not. ok) value = 0.0_wp
    message = p%message
  end subroutine evaluate_expression

  !> Record the first problem; later ones are consequences and are not kept.
  subroutine fail(p, message)
    type(parser_t), intent(inout) :: p     !< parsing state
    character(len=*), intent(in) :: message  !< what is wrong, and where
    if (.not. p%ok) return
    p%ok = .false.
    p%message = message
  end subroutine fail

  !> Skip blanks and tabs.
  subroutine skip_blanks(p)
    type(parser_t), intent(inout) :: p     !< parsing state
    do while (p%pos <= len(p%text))
      if (p%text(p%pos:p%pos) /= ' ' .and. p%text(p%pos:p%pos) /= achar(9)) exit
      p%pos = p%pos + 1
    end do
  end subroutine skip_blanks

  !> The next non-blank character ('' at the end), without consuming it.
  function peek(p) result(c)
    type(parser_t), intent(inout) :: p     !< parsing state
    character(len=:), allocatable :: c
    call skip_blanks(p)
    if (p%pos > len(p%text)) then
      c = ''
    else
      c = p%text(p%pos:p%pos)
    end if
  end function peek

  !> "column N of the expression", or "the end of the expression" past the last character.
  function where_text(p, column) result(s)
    type(parser_t), intent(in) :: p        !< parsing state
    integer, intent(in) :: column          !< the column
    character(len=:), allocatable :: s
    if (column > len(p%text)) then
      s = 'the end of the expression'
    else
      s = 'column '//itoa(column)//' of the expression'
    end if
  end function where_text

  !> expression := term { ('+' | '-') term }
  recursive function parse_sum(p) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp) :: value
    real(wp) :: right
    character(len=:), allocatable :: c
    integer :: column
    value = parse_product(p)
    do while (p%ok)
      c = peek(p)
      if (c /= '+' .and. c /= '-') exit
      column = p%pos
      p%pos = p%pos + 1
      right = parse_product(p)
      if (c == '-') right = -right
      value = checked_sum(p, value, right, c, column)
    end do
  end function parse_sum

  !> term := unary { ('*' | '/') unary }   (a '**' after an operand was taken by parse_power)
  recursive function parse_product(p) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp) :: value
    real(wp) :: right
    character(len=:), allocatable :: c
    integer :: column
    value = parse_unary(p)
    do while (p%ok)
      c = peek(p)
      if (c /= '*' .and. c /= '/') exit
      column = p%pos
      p%pos = p%pos + 1
      right = parse_unary(p)
      if (.not. p%ok) exit
      if (c == '*') then
        value = checked_product(p, value, right, column)
      else
        value = checked_quotient(p, value, right, column)
      end if
    end do
  end function parse_product

  !> unary := ('+' | '-') unary | power
  recursive function parse_unary(p) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp) :: value
    character(len=:), allocatable :: c
    c = peek(p)
    if (c == '-' .or. c == '+') then
      p%pos = p%pos + 1
      value = parse_unary(p)
      if (c == '-') value = -value
    else
      value = parse_power(p)
    end if
  end function parse_unary

  !> power := primary [ ('**' | '^') unary ]
  recursive function parse_power(p) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp) :: value
    real(wp) :: exponent
    integer :: column
    logical :: is_power
    value = parse_primary(p)
    if (.not. p%ok) return
    call skip_blanks(p)
    column = p%pos
    is_power = .false.
    if (p%pos <= len(p%text)) then
      if (p%text(p%pos:p%pos) == '^') then
        is_power = .true.
        p%pos = p%pos + 1
      else if (p%pos < len(p%text)) then
        if (p%text(p%pos:p%pos+1) == '**') then
          is_power = .true.
          p%pos = p%pos + 2
        end if
      end if
    end if
    if (.not. is_power) return
    exponent = parse_unary(p)
    if (.not. p%ok) return
    value = checked_power(p, value, exponent, column)
  end function parse_power

  !> primary := number | name | '&' name | name '(' arguments ')' | '(' expression ')'
  recursive function parse_primary(p) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp) :: value
    character(len=:), allocatable :: c, name
    integer :: column, open_column
    value = 0.0_wp
    c = peek(p)
    column = p%pos
    if (len(c) == 0) then
      call fail(p, 'the expression ends where a number, a name or ''('' is expected')
    else if (c == '(') then
      open_column = p%pos
      p%pos = p%pos + 1
      value = parse_sum(p)
      if (.not. p%ok) return
      c = peek(p)
      if (c == ')') then
        p%pos = p%pos + 1
      else if (len(c) == 0) then
        call fail(p, 'missing '')'' at the end of the expression (for the ''('' at column '// &
            itoa(open_column)//')')
      else
        call fail(p, 'unexpected '''//c//''' at column '//itoa(p%pos)//' of the expression '// &
            '('')'' expected, for the ''('' at column '//itoa(open_column)//')')
      end if
    else if (is_digit(c) .or. c == '.') then
      value = parse_number(p)
    else if (c == '&') then
      p%pos = p%pos + 1
      name = scan_name(p)
      if (len(name) == 0) then
        call fail(p, '''&'' at column '//itoa(column)//' of the expression is not followed '// &
            'by a parameter name')
      else
        value = parameter_value(p, name, column, .true.)
      end if
    else if (is_name_start(c)) then
      name = scan_name(p)
      if (peek(p) == '(') then
        value = parse_call(p, name, column)
      else
        value = parameter_value(p, name, column, .false.)
      end if
    else if (c == ')') then
      call fail(p, 'unexpected '')'' at column '//itoa(column)//' of the expression '// &
          '(a number, a name or ''('' is expected)')
    else
      call fail(p, 'unexpected '''//c//''' at column '//itoa(column)//' of the expression '// &
          '(a number, a name or ''('' is expected)')
    end if
  end function parse_primary

  !> A number: digits with an optional '.', then an optional exponent E, e, D or d with an
  !> optional sign and digits (1, 2.5, .5, 1e-3, 2.0d0).
  function parse_number(p) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp) :: value
    integer :: first, j, k, n
    logical :: ok
    first = p%pos
    n = len(p%text)
    k = first
    do while (k <= n)
      if (.not. (is_digit(p%text(k:k)) .or. p%text(k:k) == '.')) exit
      k = k + 1
    end do
    ! an exponent only when a digit follows the letter (and its sign): '2e' is 2, then 'e'
    if (k < n) then
      if (index('EeDd', p%text(k:k)) > 0) then
        j = k + 1
        if (index('+-', p%text(j:j)) > 0) j = j + 1
        if (j <= n) then
          if (is_digit(p%text(j:j))) then
            k = j
            do while (k <= n)
              if (.not. is_digit(p%text(k:k))) exit
              k = k + 1
            end do
          end if
        end if
      end if
    end if
    p%pos = k
    call parse_real(p%text(first:k-1), value, ok)
    if (.not. ok) then
      value = 0.0_wp
      call fail(p, '"'//p%text(first:k-1)//'" at column '//itoa(first)// &
          ' of the expression is not a valid number')
    end if
  end function parse_number

  !> A name (letters, digits, '_'; first a letter or '_') at the current column, consumed;
  !> '' when there is none.
  function scan_name(p) result(name)
    type(parser_t), intent(inout) :: p     !< parsing state
    character(len=:), allocatable :: name
    integer :: first
    first = p%pos
    if (p%pos <= len(p%text)) then
      if (is_name_start(p%text(p%pos:p%pos))) then
        do while (p%pos <= len(p%text))
          if (.not. (is_name_start(p%text(p%pos:p%pos)) .or. &
                     is_digit(p%text(p%pos:p%pos)))) exit
          p%pos = p%pos + 1
        end do
      end if
    end if
    name = p%text(first:p%pos-1)
  end function scan_name

  !> The value of a parameter (or of the constant pi when no parameter has that name and
  !> it is written without '&').
  function parameter_value(p, name, column, ampersand) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    character(len=*), intent(in) :: name   !< the name as written
    integer, intent(in) :: column          !< its column (of the '&' if any)
    logical, intent(in) :: ampersand       !< written as &name
    real(wp) :: value
    character(len=:), allocatable :: text
    character :: kind
    logical :: found, ok
    value = 0.0_wp
    call parameter_lookup(name, text, found, kind)
    if (.not. found) then
      if (.not. ampersand .and. to_upper(name) == 'PI') then
        value = PI
      else if (.not. ampersand .and. function_index(name) > 0) then
        call fail(p, 'function "'//name//'" at column '//itoa(column)//' of the expression '// &
            'needs its arguments in parentheses')
      else
        call fail(p, 'unknown parameter "'//name//'" at column '//itoa(column)//' of the '// &
            'expression (define it with *PARAMETER or *PARAMETER_EXPRESSION before its use)')
      end if
      return
    end if
    if (kind == 'C') then
      call fail(p, 'parameter "'//name//'" at column '//itoa(column)//' of the expression '// &
          'is a text (C) parameter, not a number')
      return
    end if
    call parse_real(text, value, ok)
    if (.not. ok) then
      value = 0.0_wp
      call fail(p, 'parameter "'//name//'" at column '//itoa(column)//' of the expression '// &
          'has the value "'//text//'", which is not a number')
    end if
  end function parameter_value

  !> name '(' expression { ',' expression } ')': a function call, '(' next.
  recursive function parse_call(p, name, column) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state at the '('
    character(len=*), intent(in) :: name   !< the function name as written
    integer, intent(in) :: column          !< its column
    real(wp) :: value
    real(wp), allocatable :: args(:), grown(:)
    character(len=:), allocatable :: c
    integer :: n, open_column, f
    value = 0.0_wp
    f = function_index(name)
    if (f == 0) then
      call fail(p, 'unknown function "'//name//'" at column '//itoa(column)//' of the '// &
          'expression')
      return
    end if
    open_column = p%pos
    p%pos = p%pos + 1
    allocate(args(4))
    n = 0
    do
      if (n == size(args)) then
        allocate(grown(2*n))
        grown(1:n) = args(1:n)
        call move_alloc(grown, args)
      end if
      n = n + 1
      args(n) = parse_sum(p)
      if (.not. p%ok) return
      c = peek(p)
      if (c == ',') then
        p%pos = p%pos + 1
      else if (c == ')') then
        p%pos = p%pos + 1
        exit
      else if (len(c) == 0) then
        call fail(p, 'missing '')'' at the end of the expression (for the ''('' of '// &
            to_lower(name)//' at column '//itoa(open_column)//')')
        return
      else
        call fail(p, 'unexpected '''//c//''' at column '//itoa(p%pos)//' of the expression '// &
            '('','' or '')'' expected in the arguments of '//to_lower(name)//')')
        return
      end if
    end do
    value = apply_function(p, trim(FUNCTION_NAMES(f)), args(1:n), column)
  end function parse_call

  !> Index of a function name in FUNCTION_NAMES (case-insensitive), 0 if none.
  integer function function_index(name)
    character(len=*), intent(in) :: name   !< the name
    integer :: k
    function_index = 0
    if (len(name) > len(FUNCTION_NAMES)) return
    do k = 1, N_FUNCTIONS
      if (to_upper(name) == FUNCTION_NAMES(k)) then
        function_index = k
        return
      end if
    end do
  end function function_index

  !> Apply function name (upper case) to its arguments, after checking their number and
  !> the function's domain.
  function apply_function(p, name, args, column) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    character(len=*), intent(in) :: name   !< the function, upper case
    real(wp), intent(in) :: args(:)        !< its arguments
    integer, intent(in) :: column          !< its column
    real(wp) :: value
    character(len=:), allocatable :: at, lname
    integer :: k
    value = 0.0_wp
    at = ' at column '//itoa(column)//' of the expression'
    lname = to_lower(name)
    select case (name)
    case ('ATAN2', 'MOD', 'SIGN')
      if (.not. argument_count(p, lname, size(args), 2, 2, column)) return
    case ('ATAN')
      if (.not. argument_count(p, lname, size(args), 1, 2, column)) return
    case ('MIN', 'MAX')
      if (.not. argument_count(p, lname, size(args), 2, huge(1), column)) return
    case default
      if (.not. argument_count(p, lname, size(args), 1, 1, column)) return
    end select
    select case (name)
    case ('ABS')
      value = abs(args(1))
    case ('SQRT')
      if (args(1) < 0.0_wp) then
        call fail(p, 'sqrt of a negative number ('//rtoa(args(1))//')'//at)
      else
        value = sqrt(args(1))
      end if
    case ('EXP')
      if (args(1) > LOG_HUGE) then
        call overflow(p, 'exp', column)
      else
        value = exp(args(1))
      end if
    case ('LOG', 'LOG10')
      if (args(1) <= 0.0_wp) then
        call fail(p, lname//' of a non-positive number ('//rtoa(args(1))//')'//at)
      else if (name == 'LOG') then
        value = log(args(1))
      else
        value = log10(args(1))
      end if
    case ('SIN')
      value = sin(args(1))
    case ('COS')
      value = cos(args(1))
    case ('TAN')
      value = tan(args(1))
    case ('ASIN', 'ACOS')
      if (abs(args(1)) > 1.0_wp) then
        call fail(p, lname//' of '//rtoa(args(1))//', outside [-1, 1],'//at)
      else if (name == 'ASIN') then
        value = asin(args(1))
      else
        value = acos(args(1))
      end if
    case ('ATAN', 'ATAN2')
      if (size(args) == 1) then
        value = atan(args(1))
      else if (args(1) == 0.0_wp .and. args(2) == 0.0_wp) then
        call fail(p, lname//'(0, 0) is undefined'//at)
      else
        value = atan2(args(1), args(2))
      end if
    case ('SINH', 'COSH')
      if (abs(args(1)) > LOG_HUGE + LOG_TWO) then
        call overflow(p, lname, column)
      else if (name == 'SINH') then
        value = sinh(args(1))
      else
        value = cosh(args(1))
      end if
    case ('TANH')
      value = tanh(args(1))
    case ('MIN')
      value = args(1)
      do k = 2, size(args)
        value = min(value, args(k))
      end do
    case ('MAX')
      value = args(1)
      do k = 2, size(args)
        value = max(value, args(k))
      end do
    case ('MOD')
      if (args(2) == 0.0_wp) then
        call fail(p, 'mod(a, 0): division by zero'//at)
      else
        value = mod(args(1), args(2))
      end if
    case ('SIGN')
      value = sign(args(1), args(2))
    case ('INT', 'AINT')
      value = aint(args(1))
    case ('NINT', 'ANINT')
      value = anint(args(1))
    end select
  end function apply_function

  !> True when a function got an acceptable number of arguments; else a message.
  logical function argument_count(p, name, got, least, most, column)
    type(parser_t), intent(inout) :: p     !< parsing state
    character(len=*), intent(in) :: name   !< the function, lower case
    integer, intent(in) :: got             !< arguments given
    integer, intent(in) :: least, most     !< arguments it takes
    integer, intent(in) :: column          !< its column
    character(len=:), allocatable :: takes
    argument_count = got >= least .and. got <= most
    if (argument_count) return
    if (least == most) then
      takes = itoa(least)//trim(merge(' argument ', ' arguments', least == 1))
    else if (most == huge(1)) then
      takes = 'at least '//itoa(least)//' arguments'
    else
      takes = itoa(least)//' or '//itoa(most)//' arguments'
    end if
    call fail(p, 'function '//name//' takes '//takes//', got '//itoa(got)//' (at column '// &
        itoa(column)//' of the expression)')
  end function argument_count

  !> Report a result beyond the double precision range.
  subroutine overflow(p, what, column)
    type(parser_t), intent(inout) :: p     !< parsing state
    character(len=*), intent(in) :: what   !< the operation
    integer, intent(in) :: column          !< its column
    call fail(p, 'the result of '//what//' at '//where_text(p, column)//' is not finite '// &
        '(beyond the double precision range)')
  end subroutine overflow

  !> a + b (b already negated for a '-'), or a message when it overflows.
  function checked_sum(p, a, b, op, column) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp), intent(in) :: a, b           !< the operands
    character(len=*), intent(in) :: op     !< '+' or '-', for the message
    integer, intent(in) :: column          !< column of the operator
    real(wp) :: value
    value = 0.0_wp
    if (.not. p%ok) return
    ! halves cannot overflow; their sum exceeds huge/2 when a + b would exceed huge
    if (abs(0.5_wp*a + 0.5_wp*b) > 0.5_wp*huge(a)) then
      call overflow(p, ''''//op//'''', column)
    else
      value = a + b
    end if
  end function checked_sum

  !> a * b, or a message when it overflows.
  function checked_product(p, a, b, column) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp), intent(in) :: a, b           !< the operands
    integer, intent(in) :: column          !< column of the operator
    real(wp) :: value
    value = 0.0_wp
    if (.not. p%ok) return
    if (a /= 0.0_wp .and. b /= 0.0_wp) then
      if (log(abs(a)) + log(abs(b)) > LOG_HUGE) then
        call overflow(p, '''*''', column)
        return
      end if
    end if
    value = a*b
  end function checked_product

  !> a / b, or a message on a division by zero or an overflow.
  function checked_quotient(p, a, b, column) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp), intent(in) :: a, b           !< the operands
    integer, intent(in) :: column          !< column of the operator
    real(wp) :: value
    value = 0.0_wp
    if (.not. p%ok) return
    if (b == 0.0_wp) then
      call fail(p, 'division by zero at column '//itoa(column)//' of the expression')
      return
    end if
    if (a /= 0.0_wp) then
      if (log(abs(a)) - log(abs(b)) > LOG_HUGE) then
        call overflow(p, '''/''', column)
        return
      end if
    end if
    value = a/b
  end function checked_quotient

  !> a ** b, or a message: 0 to a negative power (a division by zero), a negative number to
  !> a non-integral power, an overflow. An integral b is an integer power, as in Fortran.
  function checked_power(p, a, b, column) result(value)
    type(parser_t), intent(inout) :: p     !< parsing state
    real(wp), intent(in) :: a, b           !< base and exponent
    integer, intent(in) :: column          !< column of the operator
    real(wp) :: value
    real(wp) :: log_a
    logical :: integral, too_large
    value = 0.0_wp
    if (.not. p%ok) return
    integral = aint(b) == b
    if (a == 0.0_wp) then
      if (b < 0.0_wp) then
        call fail(p, 'division by zero: 0 to the negative power '//rtoa(b)//' at column '// &
            itoa(column)//' of the expression')
      else if (b == 0.0_wp) then
        value = 1.0_wp
      end if
      return
    end if
    if (a < 0.0_wp .and. .not. integral) then
      call fail(p, 'negative number ('//rtoa(a)//') to the non-integer power '//rtoa(b)// &
          ' at column '//itoa(column)//' of the expression')
      return
    end if
    ! |a|**b overflows when b log|a| > log(huge); compared without forming b log|a| (and
    ! without dividing by log|a| = 0: Fortran's .and. need not stop at a false operand)
    log_a = log(abs(a))
    too_large = .false.
    if (log_a > 0.0_wp) then
      too_large = b > LOG_HUGE/log_a
    else if (log_a < 0.0_wp) then
      too_large = b < LOG_HUGE/log_a
    end if
    if (too_large) then
      call overflow(p, '''**''', column)
      return
    end if
    if (integral .and. abs(b) < real(huge(1), wp)) then
      if (b < 0.0_wp .and. -b*log_a > LOG_HUGE) then
        value = (1.0_wp/a)**int(-b)     ! a**|b| would overflow; its inverse underflows quietly
      else
        value = a**int(b)
      end if
    else if (a > 0.0_wp) then
      value = a**b
    else                                ! a negative base to a huge even or odd power
      value = abs(a)**b
      if (mod(b, 2.0_wp) /= 0.0_wp) value = -value
    end if
  end function checked_power

  !> True for '0'-'9'.
  pure logical function is_digit(c)
    character(len=*), intent(in) :: c      !< one character ('' is no digit)
    is_digit = .false.
    if (len(c) > 0) is_digit = c(1:1) >= '0' .and. c(1:1) <= '9'
  end function is_digit

  !> True for a letter or '_' (the first character of a name).
  pure logical function is_name_start(c)
    character(len=*), intent(in) :: c      !< one character ('' is none)
    is_name_start = .false.
    if (len(c) > 0) is_name_start = (c(1:1) >= 'A' .and. c(1:1) <= 'Z') .or. &
        (c(1:1) >= 'a' .and. c(1:1) <= 'z') .or. c(1:1) == '_'
  end function is_name_start

end module mefem_expressions
