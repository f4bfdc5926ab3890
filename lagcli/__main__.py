from lagcli.cli import main

main()
